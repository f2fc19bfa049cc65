package dev.prime.bench;

/**
 * The value passed along a benchmarked chain: every block adds to it and passes it on, so no
 * block allocates and any allocation measured is the media's.
 */
public final class Packet {
  /** The running value. */
  public long value;

  /**
   * @param value the initial value
   */
  public Packet(long value) {
    this.value = value;
  }
}
