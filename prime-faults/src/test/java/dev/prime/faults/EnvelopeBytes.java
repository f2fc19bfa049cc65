package dev.prime.faults;

import java.nio.ByteBuffer;

/**
 * Entries in Optimus' wire layout, crafted from outside to attack a service: magic byte
 * {@code 'P'}, kind (0 value, 1 request, 2 reply, 3 error reply), 8-byte id, for a request the
 * reply key (2-byte length and bytes), and last the payload (1 byte "present", then the codec's
 * bytes). Written independently of the media's own envelope class, as an attacker would.
 */
final class EnvelopeBytes {
  static final byte MAGIC = 0x50;
  static final byte VALUE = 0;
  static final byte REQUEST = 1;
  static final byte REPLY_OK = 2;
  static final byte REPLY_ERROR = 3;

  private EnvelopeBytes() {}

  /** A value entry carrying {@code payload} (codec bytes; null: an absent value). */
  static byte[] value(long id, byte[] payload) {
    return build(VALUE, id, new byte[0], payload);
  }

  /** A request entry asking for the reply at {@code replyKey}. */
  static byte[] request(long id, byte[] replyKey, byte[] payload) {
    ByteBuffer key = ByteBuffer.allocate(2 + replyKey.length).putShort((short) replyKey.length).put(replyKey);
    return build(REQUEST, id, key.array(), payload);
  }

  /** A header of {@code kind} and {@code id}, followed by {@code rest} as it is. */
  static byte[] raw(byte kind, long id, byte[] rest) {
    return ByteBuffer.allocate(10 + rest.length).put(MAGIC).put(kind).putLong(id).put(rest).array();
  }

  private static byte[] build(byte kind, long id, byte[] middle, byte[] payload) {
    int payloadSize = payload == null ? 1 : 1 + payload.length;
    ByteBuffer buffer = ByteBuffer.allocate(10 + middle.length + payloadSize).put(MAGIC).put(kind).putLong(id).put(middle);
    if (payload == null) buffer.put((byte) 0); else buffer.put((byte) 1).put(payload);
    return buffer.array();
  }
}
