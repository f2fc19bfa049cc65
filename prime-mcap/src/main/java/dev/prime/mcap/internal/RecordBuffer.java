package dev.prime.mcap.internal;

import java.nio.charset.StandardCharsets;
import java.util.Arrays;
import java.util.Map;
import java.util.zip.CRC32;

/**
 * A growable little-endian byte buffer for building MCAP records: the spec's fixed-width
 * integers, length-prefixed strings and maps, and records whose content length is patched in
 * once the content is written.
 */
public final class RecordBuffer {
  private byte[] bytes;
  private int size;

  /**
   * An empty buffer.
   *
   * @param initialCapacity bytes to reserve
   */
  public RecordBuffer(int initialCapacity) {
    bytes = new byte[Math.max(16, initialCapacity)];
  }

  /** @return bytes written so far */
  public int size() {
    return size;
  }

  /** Forgets the content, keeping the storage. */
  public void clear() {
    size = 0;
  }

  /** @return the backing array (valid up to {@link #size()}) */
  public byte[] array() {
    return bytes;
  }

  /** @return a copy of the content */
  public byte[] toByteArray() {
    return Arrays.copyOf(bytes, size);
  }

  /** @return the CRC32 of the content */
  public long crc32() {
    CRC32 crc = new CRC32();
    crc.update(bytes, 0, size);
    return crc.getValue();
  }

  private void ensure(int more) {
    long needed = (long) size + more;
    if (needed > Integer.MAX_VALUE - 8) {
      throw new IllegalStateException("an MCAP record buffer cannot grow past 2 GiB");
    }
    if (needed > bytes.length) {
      bytes = Arrays.copyOf(bytes, (int) Math.min(Integer.MAX_VALUE - 8, Math.max(needed, 2L * bytes.length)));
    }
  }

  /** @param value the low 8 bits are written */
  public void u8(int value) {
    ensure(1);
    bytes[size++] = (byte) value;
  }

  /** @param value the low 16 bits are written, little-endian */
  public void u16(int value) {
    ensure(2);
    bytes[size++] = (byte) value;
    bytes[size++] = (byte) (value >>> 8);
  }

  /** @param value the low 32 bits are written, little-endian */
  public void u32(long value) {
    ensure(4);
    for (int i = 0; i < 4; i++) {
      bytes[size++] = (byte) (value >>> (8 * i));
    }
  }

  /** @param value written as 8 bytes, little-endian */
  public void u64(long value) {
    ensure(8);
    for (int i = 0; i < 8; i++) {
      bytes[size++] = (byte) (value >>> (8 * i));
    }
  }

  /**
   * Overwrites 8 bytes at a position already written.
   *
   * @param position where the uint64 starts
   * @param value the value
   */
  public void patchU64(int position, long value) {
    for (int i = 0; i < 8; i++) {
      bytes[position + i] = (byte) (value >>> (8 * i));
    }
  }

  /** @param value written as a uint32 byte length and UTF-8 bytes */
  public void string(String value) {
    byte[] utf8 = value.getBytes(StandardCharsets.UTF_8);
    u32(utf8.length);
    raw(utf8, 0, utf8.length);
  }

  /** @param value written as a uint32 byte length and the bytes */
  public void bytes32(byte[] value) {
    u32(value.length);
    raw(value, 0, value.length);
  }

  /**
   * Appends bytes with no prefix.
   *
   * @param value source
   * @param offset first byte
   * @param length count
   */
  public void raw(byte[] value, int offset, int length) {
    ensure(length);
    System.arraycopy(value, offset, bytes, size, length);
    size += length;
  }

  /** @param map written as the spec's {@code Map<string, string>} */
  public void stringMap(Map<String, String> map) {
    int lengthAt = size;
    u32(0);
    int start = size;
    for (Map.Entry<String, String> e : map.entrySet()) {
      string(e.getKey());
      string(e.getValue());
    }
    patchU32(lengthAt, size - start);
  }

  /** @param map written as the spec's {@code Map<uint16, uint64>} */
  public void u16u64Map(Map<Integer, Long> map) {
    u32(map.size() * 10L);
    for (Map.Entry<Integer, Long> e : map.entrySet()) {
      u16(e.getKey());
      u64(e.getValue());
    }
  }

  private void patchU32(int position, long value) {
    for (int i = 0; i < 4; i++) {
      bytes[position + i] = (byte) (value >>> (8 * i));
    }
  }

  /**
   * Starts a record: writes the opcode and a content length to patch with {@link #endRecord}.
   *
   * @param opcode the record's opcode
   * @return the position to pass to {@link #endRecord}
   */
  public int beginRecord(int opcode) {
    u8(opcode);
    int lengthAt = size;
    u64(0);
    return lengthAt;
  }

  /**
   * Ends a record begun with {@link #beginRecord}: patches its content length.
   *
   * @param lengthAt what {@link #beginRecord} returned
   */
  public void endRecord(int lengthAt) {
    patchU64(lengthAt, size - lengthAt - 8L);
  }
}
