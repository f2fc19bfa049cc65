package dev.prime.bench;

import dev.prime.Block;
import dev.prime.bench.PacketBlocks.Add;
import dev.prime.bench.PacketBlocks.Clamp;
import dev.prime.bench.PacketBlocks.Multiply;
import dev.prime.bench.PacketBlocks.Negate;
import dev.prime.bench.PacketBlocks.Shift;
import dev.prime.bench.PacketBlocks.Xor;
import java.util.List;

/**
 * The unavoidable cost of a polluted profile: blocks called in a loop through one
 * {@code Block.process} call site that has seen six block classes in equal numbers, so the JIT
 * cannot inline any of them and every block is an interface dispatch. A media whose shared code
 * sees many block classes cannot do better than this per block; one that does worse adds layers.
 */
public final class MegamorphicSite {
  /** Calls through the site per pollution round: enough for the JIT's profile to count them. */
  private static final int POLLUTING_RUNS = 20_000;

  private MegamorphicSite() {}

  /**
   * Runs the blocks in order through the one shared call site.
   *
   * @param blocks the blocks
   * @param packet the input
   * @return the output of the last block
   */
  public static Packet run(Block<Packet, Packet>[] blocks, Packet packet) {
    Packet result = packet;
    for (Block<Packet, Packet> block : blocks) {
      result = block.process(result);
    }
    return result;
  }

  /**
   * The blocks in an array whose element type is {@code Block} (not their own class).
   *
   * @param blocks the blocks
   * @return a new array of them
   */
  public static Block<Packet, Packet>[] typed(List<? extends Block<Packet, Packet>> blocks) {
    @SuppressWarnings("unchecked")
    Block<Packet, Packet>[] typed = (Block<Packet, Packet>[]) new Block<?, ?>[blocks.size()];
    for (int i = 0; i < typed.length; i++) {
      typed[i] = blocks.get(i);
    }
    return typed;
  }

  /**
   * Drives the site with six block classes, each as often as the others, so its profile is
   * megamorphic however many {@link Add}s are measured through it afterwards.
   *
   * @return a value that depends on every call (give it to a Blackhole or a field)
   */
  public static long pollute() {
    Block<Packet, Packet>[] mixed =
        typed(
            List.of(
                new Multiply(3), new Xor(0x55), new Shift(1), new Clamp(1 << 20), new Negate(),
                new Add(7)));
    Packet packet = new Packet(1);
    long sum = 0;
    for (int i = 0; i < POLLUTING_RUNS; i++) {
      packet.value = i;
      sum += run(mixed, packet).value;
    }
    return sum;
  }
}
