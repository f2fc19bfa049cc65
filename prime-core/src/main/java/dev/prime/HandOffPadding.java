package dev.prime;

/**
 * Cache-line padding of the in-memory hand-off's hot fields, by class hierarchy: the JVM lays out
 * a superclass's fields before its subclass's, so a field declared between two classes of 16
 * unused longs (128 bytes, two cache lines, for CPUs that fetch lines in pairs) shares no cache
 * line with the object's other fields or with a neighbouring object.
 *
 * <p>Design: {@link MemorySource}'s publishers write {@code claimed} and {@code count} once per
 * value and its readers read them; a reader's {@code cursor} is written once per value by the
 * thread that reads and read by publishers only when they might lap it. Unpadded, these fields sat
 * next to fields the other thread reads ({@code ring}, {@code closed}, a reader's {@code
 * readerClosed}) and, depending on where the allocator put a reader, next to its source's counters:
 * every value then moved a cache line between the cores once more (false sharing). The padding is
 * plain {@code long} fields nobody reads; {@code @Contended} would do the same but needs {@code
 * -XX:-RestrictContended} outside the JDK.
 */
final class HandOffPadding {
  private HandOffPadding() {}

  /** Two cache lines of padding before the hot fields (and after the object header). */
  abstract static class PadBefore {
    long p00, p01, p02, p03, p04, p05, p06, p07, p08, p09, p10, p11, p12, p13, p14, p15;
  }

  /** A source's publication counters: see {@link MemorySource} for what they mean. */
  abstract static class Sequences extends PadBefore {
    /** The publishers' token: {@code count}, or {@code count + 1} while a publisher holds it. */
    volatile long claimed;

    /** Values fully published; written by the token's holder. */
    volatile long count;
  }

  /** Two cache lines of padding after a source's counters. */
  abstract static class PaddedSequences extends Sequences {
    long q00, q01, q02, q03, q04, q05, q06, q07, q08, q09, q10, q11, q12, q13, q14, q15;
  }

  /** A reader's cursor: the sequence number of its next value. */
  abstract static class Cursor extends PadBefore {
    /** Moved by compare-and-set, or by release stores of a service input's only consumer. */
    volatile long cursor;

    /**
     * @param cursor the first sequence number to read
     */
    Cursor(long cursor) {
      this.cursor = cursor;
    }
  }

  /** Two cache lines of padding after a reader's cursor. */
  abstract static class PaddedCursor extends Cursor {
    long q00, q01, q02, q03, q04, q05, q06, q07, q08, q09, q10, q11, q12, q13, q14, q15;

    /**
     * @param cursor the first sequence number to read
     */
    PaddedCursor(long cursor) {
      super(cursor);
    }
  }
}
