package dev.prime.mcap;

/**
 * A message decoded into the type its reader named.
 *
 * @param topic its channel's topic
 * @param sequence its sequence number (0..2^32-1)
 * @param logTime log time, nanoseconds
 * @param publishTime publish time, nanoseconds
 * @param value the value
 * @param <T> the value's type
 */
public record TypedMessage<T>(String topic, long sequence, long logTime, long publishTime, T value) {}
