package dev.prime.bench;

/**
 * The value passed along a benchmarked chain: every block adds to it and passes it on, so no
 * block allocates and any allocation measured is the media's. The payload stands for the data of
 * the paper's experiment (100 B, 1 KB, 10 KB); no block reads or copies it, as no local media
 * serializes it.
 */
public final class Packet {
  /** The running value. */
  public long value;

  /** The data carried along; never copied. */
  public final byte[] payload;

  /**
   * A packet without payload.
   *
   * @param value the initial value
   */
  public Packet(long value) {
    this(value, new byte[0]);
  }

  /**
   * @param value the initial value
   * @param payload the data carried along
   */
  public Packet(long value, byte[] payload) {
    this.value = value;
    this.payload = payload;
  }

  /**
   * A packet carrying {@code bytes} bytes of data.
   *
   * @param bytes the payload's size
   * @return the packet, value 0
   */
  public static Packet ofSize(int bytes) {
    if (bytes < 0) {
      throw new IllegalArgumentException("payload must be 0 bytes or more, was " + bytes);
    }
    byte[] payload = new byte[bytes];
    for (int i = 0; i < bytes; i++) {
      payload[i] = (byte) i;
    }
    return new Packet(0, payload);
  }
}
