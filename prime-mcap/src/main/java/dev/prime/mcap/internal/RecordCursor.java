package dev.prime.mcap.internal;

import java.nio.ByteBuffer;
import java.nio.ByteOrder;
import java.nio.charset.CharacterCodingException;
import java.nio.charset.CodingErrorAction;
import java.nio.charset.StandardCharsets;
import java.util.LinkedHashMap;
import java.util.Map;

/**
 * Reads the spec's little-endian fields from a byte range, checking every length against what
 * is left: a field that runs past its record is reported (through the caller's exception
 * factory, with the file offset), never read from the next record.
 */
public final class RecordCursor {
  private final ByteBuffer buffer;
  private final long fileOffset;
  private final String what;
  private final Problem problem;

  /** Makes the exception for a malformed field. */
  @FunctionalInterface
  public interface Problem {
    /**
     * @param offset file offset of the field
     * @param message what is wrong
     * @return the exception to throw
     */
    RuntimeException at(long offset, String message);
  }

  /**
   * @param bytes the bytes
   * @param offset first byte
   * @param length byte count
   * @param fileOffset the file offset of {@code bytes[offset]}
   * @param what what the range is, for messages ("Channel record")
   * @param problem makes the exception for a malformed field
   */
  public RecordCursor(byte[] bytes, int offset, int length, long fileOffset, String what, Problem problem) {
    this.buffer = ByteBuffer.wrap(bytes, offset, length).slice().order(ByteOrder.LITTLE_ENDIAN);
    this.fileOffset = fileOffset;
    this.what = what;
    this.problem = problem;
  }

  /** @return bytes left */
  public int remaining() {
    return buffer.remaining();
  }

  /** @return the file offset of the next byte */
  public long fileOffset() {
    return fileOffset + buffer.position();
  }

  /** @return the position within the range */
  public int position() {
    return buffer.position();
  }

  /**
   * Checks that {@code bytes} more can be read. A length read from a uint64 may be 2^63 or more,
   * a negative long: that is past any record too, and is reported unsigned.
   */
  private void need(long bytes, String field) {
    if (bytes < 0 || bytes > buffer.remaining()) {
      throw problem.at(fileOffset(),
          what + ": field " + field + " needs " + Long.toUnsignedString(bytes) + " bytes but only "
              + buffer.remaining() + " are left (the record is cut short or its length is wrong)");
    }
  }

  /**
   * @param field field name, for messages
   * @return a uint8
   */
  public int u8(String field) {
    need(1, field);
    return buffer.get() & 0xFF;
  }

  /**
   * @param field field name, for messages
   * @return a uint16
   */
  public int u16(String field) {
    need(2, field);
    return buffer.getShort() & 0xFFFF;
  }

  /**
   * @param field field name, for messages
   * @return a uint32
   */
  public long u32(String field) {
    need(4, field);
    return buffer.getInt() & 0xFFFFFFFFL;
  }

  /**
   * @param field field name, for messages
   * @return a uint64 (as a signed long: values past 2^63 come out negative)
   */
  public long u64(String field) {
    need(8, field);
    return buffer.getLong();
  }

  /**
   * @param field field name, for messages
   * @return a length-prefixed UTF-8 string
   */
  public String string(String field) {
    long length = u32(field + " length");
    byte[] bytes = bytes(length, field);
    try {
      return StandardCharsets.UTF_8.newDecoder()
          .onMalformedInput(CodingErrorAction.REPORT)
          .onUnmappableCharacter(CodingErrorAction.REPORT)
          .decode(ByteBuffer.wrap(bytes))
          .toString();
    } catch (CharacterCodingException e) {
      throw problem.at(fileOffset() - length, what + ": field " + field + " is not valid UTF-8");
    }
  }

  /**
   * @param length byte count
   * @param field field name, for messages
   * @return the next {@code length} bytes
   */
  public byte[] bytes(long length, String field) {
    need(length, field);
    byte[] out = new byte[(int) length];
    buffer.get(out);
    return out;
  }

  /**
   * @param field field name, for messages
   * @return uint32-length-prefixed bytes
   */
  public byte[] bytes32(String field) {
    return bytes(u32(field + " length"), field);
  }

  /**
   * @param field field name, for messages
   * @return a {@code Map<string, string>}
   */
  public Map<String, String> stringMap(String field) {
    long length = u32(field + " length");
    need(length, field);
    int end = buffer.position() + (int) length;
    Map<String, String> map = new LinkedHashMap<>();
    while (buffer.position() < end) {
      String key = string(field + " key");
      map.put(key, string(field + " value"));
    }
    checkEnd(end, field);
    return map;
  }

  /**
   * @param field field name, for messages
   * @return a {@code Map<uint16, uint64>}
   */
  public Map<Integer, Long> u16u64Map(String field) {
    long length = u32(field + " length");
    need(length, field);
    if (length % 10 != 0) {
      throw problem.at(fileOffset(), what + ": field " + field + " is " + length
          + " bytes, not a whole number of uint16/uint64 pairs");
    }
    Map<Integer, Long> map = new LinkedHashMap<>();
    for (long i = 0; i < length / 10; i++) {
      int key = u16(field + " key");
      map.put(key, u64(field + " value"));
    }
    return map;
  }

  private void checkEnd(int end, String field) {
    if (buffer.position() != end) {
      throw problem.at(fileOffset(), what + ": field " + field + " entries overrun its length");
    }
  }
}
