package dev.prime.bench;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.Source;
import dev.prime.Token;
import dev.prime.liberty.LibertyCore;
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
 * Prime sources in synchronous mode (the paper's "dispatcher"): the caller publishes one packet to
 * an event block, the 4-adder chain linked to its source runs on the core's service thread, and a
 * {@link dev.prime.PrimeCore#syncCollector} chain returns the output before the next packet is
 * published. So every transmission is two thread hand-offs, there and back.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class SyncSourceBenchmark {

  /** An event block, its source in a Liberty core, the linked chain and a collector. */
  @State(Scope.Thread)
  public static class Collected {
    /** Where the benchmark publishes. */
    public EventBlock<Packet> events;

    /** Returns the chain's next output. */
    public Block<Token, Packet> collector;

    /** What the collector is called with. */
    public Token token = Token.INSTANCE;

    private LibertyCore core;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      core = new LibertyCore();
      events = new EventBlock<>();
      Source<Packet> output =
          core.source(events).then(ChainShapes.adderChain(core, shape.length));
      collector = core.syncCollector(output).toBlock();
      core.start();
    }

    /** Closes the core and its service thread. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /**
   * One packet there and its output back.
   *
   * @param input the packet
   * @param source the source, chain and collector
   * @return the output's value
   */
  @Benchmark
  public long primeSource(SyncChainBenchmark.Input input, Collected source) {
    source.events.publish(input.packet);
    return source.collector.process(source.token).value;
  }
}
