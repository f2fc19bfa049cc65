package dev.prime.mcap;

import java.util.Objects;
import java.util.concurrent.atomic.LongAdder;

/**
 * A typed channel of an {@link McapWriter}: one topic, one value type, JSON messages with the
 * type's JSON Schema. Made by {@link McapWriter#channel}; safe to use from any thread.
 *
 * @param <T> the type of the values
 */
public final class McapChannel<T> {
  private final McapWriter writer;
  private final int id;
  private final String topic;
  private final ValueType<T> type;
  private final LongAdder dropped = new LongAdder();

  McapChannel(McapWriter writer, int id, String topic, ValueType<T> type) {
    this.writer = writer;
    this.id = id;
    this.topic = topic;
    this.type = type;
  }

  /**
   * Records one value. The value is encoded to JSON in the calling thread (so later changes to
   * a mutable value do not reach the file) and handed to the writer; with a queue this never
   * waits: when the queue is full the message is dropped and counted.
   *
   * @param logTimeNanos when it was recorded, nanoseconds since an epoch of the caller's choice
   *     (not negative)
   * @param publishTimeNanos when it was published (not negative; pass the log time if unknown)
   * @param sequence a sequence number for gap detection; MCAP keeps its low 32 bits
   * @param value the value (not null)
   * @return true if the message was accepted, false if it was dropped (queue full, or the
   *     background writer failed earlier: {@link McapWriter#close()} then throws that failure)
   * @throws IllegalArgumentException for a negative time, a value Jackson cannot write, or (with
   *     a queue) a message larger than the queue's byte bound ({@link McapWriterOptions#queue}),
   *     which could never be queued
   * @throws IllegalStateException if the writer is closed
   */
  public boolean write(long logTimeNanos, long publishTimeNanos, long sequence, T value) {
    Objects.requireNonNull(value, () -> "a value written to MCAP channel '" + topic + "' is null");
    checkTimes(topic, logTimeNanos, publishTimeNanos);
    return writer.submit(this, sequence, logTimeNanos, publishTimeNanos, type.toJson(value));
  }

  /** Refuses a negative time, as {@link #write} does. */
  static void checkTimes(String topic, long logTimeNanos, long publishTimeNanos) {
    if (logTimeNanos < 0 || publishTimeNanos < 0) {
      throw new IllegalArgumentException(
          "MCAP times are unsigned nanoseconds: log time " + logTimeNanos + " and publish time "
              + publishTimeNanos + " on '" + topic + "' must not be negative");
    }
  }

  /**
   * Writes a message whose value is encoded already ({@link ValueType#toJson} of this channel's
   * type), its times checked with {@link #checkTimes} already: for a caller that encodes every
   * value before the writer opens, so that a value that cannot be written fails before the path
   * is touched.
   */
  boolean writeJson(long logTimeNanos, long publishTimeNanos, long sequence, byte[] json) {
    return writer.submit(this, sequence, logTimeNanos, publishTimeNanos, json);
  }

  /** @return the channel's id in the files */
  public int id() {
    return id;
  }

  /** @return the topic */
  public String topic() {
    return topic;
  }

  /** @return the value type */
  public ValueType<T> type() {
    return type;
  }

  /** @return messages of this channel dropped so far */
  public long droppedCount() {
    return dropped.sum();
  }

  void countDrop() {
    dropped.increment();
  }

  @Override
  public String toString() {
    return "McapChannel[" + id + " '" + topic + "' " + type.name() + "]";
  }
}
