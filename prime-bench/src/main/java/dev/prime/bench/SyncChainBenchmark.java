package dev.prime.bench;

import dev.prime.Block;
import dev.prime.bench.PacketBlocks.Add;
import dev.prime.liberty.LibertyCore;
import dev.prime.radiant.RadiantCore;
import java.util.List;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;

/**
 * The paper's synchronous experiment: time per transmission through a chain of blocks that each
 * add a number, for FOR (the blocks called directly in a loop), Liberty and Radiant.
 *
 * <p>Each (method, length, scenario) runs in forks of its own, so the monomorphic scenario really
 * has one chain shape in its JVM. Inputs come from non-final state fields and every result is
 * returned to JMH, so nothing folds to a constant. See README.md for the commands.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class SyncChainBenchmark {

  /** The value sent along the chain; it keeps changing, so no result is a constant. */
  @State(Scope.Thread)
  public static class Input {
    /** The packet, carrying {@link Shape#payload} bytes. */
    public Packet packet;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      packet = Packet.ofSize(shape.payload);
    }
  }

  /** FOR: the same blocks, held and called directly. */
  @State(Scope.Thread)
  public static class Direct {
    /** The blocks, by their own class. */
    public Add[] adders;

    /** The blocks of a 4-block chain in fields, for {@link #forHandWritten}. */
    public Add a1;

    /** Second block. */
    public Add a2;

    /** Third block. */
    public Add a3;

    /** Fourth block. */
    public Add a4;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      adders = ChainShapes.directAdders(shape.length);
      if (shape.length == 4) {
        a1 = adders[0];
        a2 = adders[1];
        a3 = adders[2];
        a4 = adders[3];
      }
    }
  }

  /**
   * The baseline of a polluted profile: the same blocks as {@link Direct}, called through
   * {@link MegamorphicSite}'s one call site, polluted with six block classes before warm-up and
   * again before every iteration, in both scenarios.
   */
  @State(Scope.Thread)
  public static class Megamorphic {
    /** The blocks, typed as blocks. */
    public Block<Packet, Packet>[] blocks;

    /** Keeps the polluting runs' results alive. */
    public long sink;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      blocks = MegamorphicSite.typed(List.of(ChainShapes.directAdders(shape.length)));
      pollute();
    }

    /** Pollutes the call site again, so the measured blocks never dominate its profile. */
    @Setup(Level.Iteration)
    public void pollute() {
      sink += MegamorphicSite.pollute();
    }
  }

  /** The chain as a Liberty block. */
  @State(Scope.Thread)
  public static class Liberty {
    /** The linked chain's block. */
    public Block<Packet, Packet> chain;

    private LibertyCore core;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      core = new LibertyCore();
      chain = ChainShapes.adders(core, shape.length);
    }

    /** Closes the core. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /** The chain as a Radiant block. */
  @State(Scope.Thread)
  public static class Radiant {
    /** The linked chain's block. */
    public Block<Packet, Packet> chain;

    private RadiantCore core;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      core = new RadiantCore();
      chain = ChainShapes.adders(core, shape.length);
    }

    /** Closes the core. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /**
   * FOR: direct calls in a loop.
   *
   * @param input the value
   * @param blocks the blocks
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long forLoop(Input input, Direct blocks, WorkerCpuTime.Clock clock) {
    Packet packet = input.packet;
    for (Add adder : blocks.adders) {
      packet = adder.process(packet);
    }
    return packet.value;
  }

  /**
   * FOR, written out by hand for the paper's 4-block chain (fails for other lengths: select it
   * only with {@code -p length=4}).
   *
   * @param input the value
   * @param blocks the blocks
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long forHandWritten(Input input, Direct blocks, WorkerCpuTime.Clock clock) {
    return blocks.a4.process(blocks.a3.process(blocks.a2.process(blocks.a1.process(input.packet))))
        .value;
  }

  /**
   * The unavoidable cost of a polluted profile: the same blocks through one megamorphic call site
   * (compare polluted Liberty with it).
   *
   * @param input the value
   * @param blocks the blocks
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long megamorphic(Input input, Megamorphic blocks, WorkerCpuTime.Clock clock) {
    return MegamorphicSite.run(blocks.blocks, input.packet).value;
  }

  /**
   * Liberty: composed functions.
   *
   * @param input the value
   * @param chain the chain
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long liberty(Input input, Liberty chain, WorkerCpuTime.Clock clock) {
    return chain.chain.process(input.packet).value;
  }

  /**
   * Radiant: one generated class.
   *
   * @param input the value
   * @param chain the chain
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long radiant(Input input, Radiant chain, WorkerCpuTime.Clock clock) {
    return chain.chain.process(input.packet).value;
  }
}
