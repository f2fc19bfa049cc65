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
 * every value then moved a cache line between the cores once more (false sharing). {@code claimed}
 * and {@code count} are on lines of their own too: a service's input watches only {@code count},
 * so the publisher's compare-and-set of {@code claimed} finds its line where it left it. The padding is
 * plain {@code long} fields nobody reads; {@code @Contended} would do the same but needs {@code
 * -XX:-RestrictContended} outside the JDK.
 */
final class HandOffPadding {
  private HandOffPadding() {}

  /** Two cache lines of padding before the hot fields (and after the object header). */
  abstract static class PadBefore {
    long p00, p01, p02, p03, p04, p05, p06, p07, p08, p09, p10, p11, p12, p13, p14, p15;
  }

  /** A source's publishers' token: see {@link MemorySource} for what it means. */
  abstract static class Claimed extends PadBefore {
    /** The publishers' token: {@code count}, or {@code count + 1} while a publisher holds it. */
    volatile long claimed;
  }

  /** Two cache lines between the token and the count. */
  abstract static class PadBetween extends Claimed {
    long m00, m01, m02, m03, m04, m05, m06, m07, m08, m09, m10, m11, m12, m13, m14, m15;
  }

  /** A source's publication count, after its token and padding. */
  abstract static class Sequences extends PadBetween {
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
