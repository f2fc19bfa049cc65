package dev.prime.bench;

import dev.prime.Block;

/**
 * The blocks of the benchmarks: plain logic-layer classes. {@link Add} makes the measured chain;
 * the others exist so the polluted scenario can build chains of many shapes and block classes, as
 * a real controller has.
 */
public final class PacketBlocks {
  private PacketBlocks() {}

  /** Adds a number: the block of the paper's synchronous experiment. */
  public static final class Add implements Block<Packet, Packet> {
    private final long amount;

    /**
     * @param amount what is added
     */
    public Add(long amount) {
      this.amount = amount;
    }

    @Override
    public Packet process(Packet packet) {
      packet.value += amount;
      return packet;
    }
  }

  /** Multiplies by a number. */
  public static final class Multiply implements Block<Packet, Packet> {
    private final long factor;

    /**
     * @param factor the factor
     */
    public Multiply(long factor) {
      this.factor = factor;
    }

    @Override
    public Packet process(Packet packet) {
      packet.value *= factor;
      return packet;
    }
  }

  /** Flips bits. */
  public static final class Xor implements Block<Packet, Packet> {
    private final long mask;

    /**
     * @param mask the bits to flip
     */
    public Xor(long mask) {
      this.mask = mask;
    }

    @Override
    public Packet process(Packet packet) {
      packet.value ^= mask;
      return packet;
    }
  }

  /** Shifts right. */
  public static final class Shift implements Block<Packet, Packet> {
    private final int bits;

    /**
     * @param bits how far
     */
    public Shift(int bits) {
      this.bits = bits;
    }

    @Override
    public Packet process(Packet packet) {
      packet.value >>>= bits;
      return packet;
    }
  }

  /** Keeps the value within a bound. */
  public static final class Clamp implements Block<Packet, Packet> {
    private final long bound;

    /**
     * @param bound the largest magnitude kept
     */
    public Clamp(long bound) {
      this.bound = bound;
    }

    @Override
    public Packet process(Packet packet) {
      packet.value = Math.max(-bound, Math.min(bound, packet.value));
      return packet;
    }
  }

  /** Negates. */
  public static final class Negate implements Block<Packet, Packet> {
    @Override
    public Packet process(Packet packet) {
      packet.value = -packet.value;
      return packet;
    }
  }
}
