package dev.prime.bench;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.PrimeCore;
import dev.prime.bench.PacketBlocks.Add;
import dev.prime.bench.PacketBlocks.Clamp;
import dev.prime.bench.PacketBlocks.Multiply;
import dev.prime.bench.PacketBlocks.Negate;
import dev.prime.bench.PacketBlocks.Shift;
import dev.prime.bench.PacketBlocks.Xor;
import java.util.ArrayList;
import java.util.List;

/** Builds the benchmarked chains on any core. */
public final class ChainShapes {
  /** How many calls drive each polluting chain per round. */
  private static final int DRIVE_CALLS = 20_000;

  private ChainShapes() {}

  /**
   * The measured chain: {@code length} blocks that each add a different number.
   *
   * @param core the media
   * @param length number of blocks
   * @return the chain's block
   */
  public static Block<Packet, Packet> adders(PrimeCore core, int length) {
    return adderChain(core, length).toBlock();
  }

  /**
   * The measured chain, not yet turned into a block (to link it to a source).
   *
   * @param core the media
   * @param length number of blocks
   * @return the chain
   */
  public static Chain<Packet, Packet> adderChain(PrimeCore core, int length) {
    Chain<Packet, Packet> chain = core.chain(new Add(1));
    for (int i = 2; i <= length; i++) {
      chain = chain.then(new Add(i));
    }
    return chain;
  }

  /**
   * Runs the FOR blocks on a packet: what a peer (Flow, Reactor, Disruptor) runs per value.
   *
   * @param adders the blocks
   * @param packet the packet
   * @return the packet after every block
   */
  public static Packet runDirect(Add[] adders, Packet packet) {
    Packet result = packet;
    for (Add adder : adders) {
      result = adder.process(result);
    }
    return result;
  }

  /**
   * The measured chain for the FOR baseline: the same blocks, called directly.
   *
   * @param length number of blocks
   * @return the blocks
   */
  public static Add[] directAdders(int length) {
    Add[] adders = new Add[length];
    for (int i = 0; i < length; i++) {
      adders[i] = new Add(i + 1);
    }
    return adders;
  }

  /**
   * Ten chains of other shapes and block classes (links, if/else, guard), as a controller has.
   *
   * @param core the media
   * @return their blocks
   */
  public static List<Block<Packet, Packet>> polluters(PrimeCore core) {
    List<Block<Packet, Packet>> blocks = new ArrayList<>();
    blocks.add(linked(core, new Add(3), new Multiply(3)));
    blocks.add(linked(core, new Xor(0x55), new Shift(1), new Add(7)));
    blocks.add(linked(core, new Negate(), new Add(2), new Multiply(5), new Xor(9), new Shift(2)));
    blocks.add(linked(core, new Clamp(1_000_000), new Add(1), new Negate()));
    blocks.add(linked(core, new Shift(3), new Shift(1), new Multiply(7), new Add(11)));
    blocks.add(
        linked(core, new Clamp(1 << 20), new Add(5), new Xor(3), new Multiply(3), new Add(1),
            new Shift(1)));
    blocks.add(linked(core, new Multiply(31), new Xor(0xF0F0)));
    blocks.add(linked(core, new Add(8), new Add(9), new Add(10)));
    blocks.add(
        core.ifThenElse(
                (Packet p) -> (p.value & 1) == 0,
                core.chain(new Multiply(3)).then(new Add(1)),
                core.chain(new Shift(1)).then(new Negate()))
            .then(new Clamp(1 << 30))
            .toBlock());
    blocks.add(
        core.guard(
                (Packet p) -> p.value > 0,
                core.chain(new Xor(0xFF)).then(new Add(2)).then(new Shift(1)),
                (Packet p) -> p)
            .then(new Clamp(1 << 24))
            .toBlock());
    return blocks;
  }

  /**
   * Calls every block many times with changing values, so the JIT profiles them.
   *
   * @param blocks the polluting chains
   * @return a value that depends on every call (give it to a Blackhole)
   */
  public static long drive(List<Block<Packet, Packet>> blocks) {
    Packet packet = new Packet(1);
    long sum = 0;
    for (int i = 0; i < DRIVE_CALLS; i++) {
      for (Block<Packet, Packet> block : blocks) {
        packet.value = i;
        sum += block.process(packet).value;
      }
    }
    return sum;
  }

  @SafeVarargs
  private static Block<Packet, Packet> linked(PrimeCore core, Block<Packet, Packet>... blocks) {
    Chain<Packet, Packet> chain = core.chain(blocks[0]);
    for (int i = 1; i < blocks.length; i++) {
      chain = chain.then(blocks[i]);
    }
    return chain.toBlock();
  }
}
