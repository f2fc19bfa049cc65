package dev.prime;

/** The empty input of a collector chain: "give me what you have". */
public enum Token {
  /** The only token. */
  INSTANCE
}
