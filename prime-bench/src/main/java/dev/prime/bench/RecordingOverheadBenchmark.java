package dev.prime.bench;

import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.Source;
import dev.prime.Token;
import dev.prime.bench.PacketBlocks.Add;
import dev.prime.liberty.LibertyCore;
import dev.prime.radiant.RadiantCore;
import java.util.concurrent.TimeUnit;
import java.util.function.Function;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;

/**
 * What recording (issue 11, {@link CoreConfig.Builder#recording}) costs per transmission: the
 * synchronous table's Liberty, Radiant and sources rows, built exactly as in {@link
 * SyncChainBenchmark} and {@link SyncSourceBenchmark}, in two scenarios: {@code recordingOff}
 * (the default {@link CoreConfig}, so these rows must equal the synchronous table's monomorphic
 * rows) and {@code recordingOn} ({@link RecordingOptions#defaults()}: a ring of 10,000 values per
 * name, so every block's output and every published packet is stamped and stored). The FOR row
 * is the baseline of both tables.
 *
 * <p>Each (method, payload, scenario) runs in forks of its own, so an "off" fork never loaded the
 * recording classes. Recorded per transmission when on: the output of each of the 4 adders, and
 * in the sources row the published packet too (5 entries, each an {@code Instant}, a {@code
 * System.nanoTime()} and a {@code RecordedValue} under the ring's monitor).
 *
 * <p>On a loaded machine add {@code -prof dev.prime.bench.WorkerCpuTime}: the FOR, Liberty and
 * Radiant rows then also give the benchmark thread's CPU time per operation ({@code
 * cpu.time.norm}), which does not grow when other processes take the cores away.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class RecordingOverheadBenchmark {

  /** The parameters the suite passes: the chain's length, the packet's size and the scenario. */
  @State(Scope.Thread)
  public static class Setting {
    /** Blocks in the chain (the suite passes 4). */
    @Param({"4"})
    public int length;

    /** Bytes each packet carries. */
    @Param({"100", "1024", "10240"})
    public int payload;

    /** {@code recordingOff} or {@code recordingOn}. */
    @Param({"recordingOff", "recordingOn"})
    public String scenario;

    /** The packet sent along the chain. */
    public Packet packet;

    /** Makes the packet and checks the scenario. */
    @Setup(Level.Trial)
    public void build() {
      config(); // refuses an unknown scenario before anything runs
      packet = Packet.ofSize(payload);
    }

    /**
     * {@return the core's settings for the scenario}
     *
     * @throws IllegalArgumentException for an unknown scenario
     */
    public CoreConfig config() {
      return switch (scenario) {
        case "recordingOff" -> CoreConfig.defaults();
        case "recordingOn" ->
            CoreConfig.builder().recording(RecordingOptions.defaults()).build();
        default -> throw new IllegalArgumentException(
            "scenario must be recordingOff or recordingOn, not " + scenario);
      };
    }
  }

  /** FOR: the 4 blocks held in fields and called directly. */
  @State(Scope.Thread)
  public static class Direct {
    /** First block. */
    public Add a1;

    /** Second block. */
    public Add a2;

    /** Third block. */
    public Add a3;

    /** Fourth block. */
    public Add a4;

    /**
     * @param setting the parameters
     */
    @Setup(Level.Trial)
    public void build(Setting setting) {
      if (setting.length != 4) {
        throw new IllegalArgumentException("the FOR baseline is written for -p length=4");
      }
      Add[] adders = ChainShapes.directAdders(4);
      a1 = adders[0];
      a2 = adders[1];
      a3 = adders[2];
      a4 = adders[3];
    }
  }

  /** A linked chain's block in a core of the scenario. */
  public abstract static class ChainState {
    /** The linked chain's block. */
    public Block<Packet, Packet> chain;

    private PrimeCore core;

    void build(Setting setting, Function<CoreConfig, PrimeCore> media) {
      core = media.apply(setting.config());
      chain = ChainShapes.adders(core, setting.length);
    }

    /** {@return the core (for the benchmark's own test)} */
    PrimeCore core() {
      return core;
    }

    /** Closes the core. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /** The chain as a Liberty block. */
  @State(Scope.Thread)
  public static class Liberty extends ChainState {
    /**
     * @param setting the parameters
     */
    @Setup(Level.Trial)
    public void build(Setting setting) {
      build(setting, LibertyCore::new);
    }
  }

  /** The chain as a Radiant block. */
  @State(Scope.Thread)
  public static class Radiant extends ChainState {
    /**
     * @param setting the parameters
     */
    @Setup(Level.Trial)
    public void build(Setting setting) {
      build(setting, RadiantCore::new);
    }
  }

  /** As {@link SyncSourceBenchmark}: an event block, its source, the linked chain, a collector. */
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
     * @param setting the parameters
     */
    @Setup(Level.Trial)
    public void build(Setting setting) {
      core = new LibertyCore(setting.config());
      events = new EventBlock<>();
      Source<Packet> output =
          core.source(events).then(ChainShapes.adderChain(core, setting.length));
      collector = core.syncCollector(output).toBlock();
      core.start();
    }

    /** {@return the core (for the benchmark's own test)} */
    PrimeCore core() {
      return core;
    }

    /** Closes the core and its service thread. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /**
   * FOR, the baseline.
   *
   * @param setting the packet
   * @param blocks the blocks
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long forHandWritten(Setting setting, Direct blocks, WorkerCpuTime.PlainClock clock) {
    return blocks.a4.process(blocks.a3.process(blocks.a2.process(blocks.a1.process(setting.packet))))
        .value;
  }

  /**
   * Liberty.
   *
   * @param setting the packet
   * @param chain the chain
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long liberty(Setting setting, Liberty chain, WorkerCpuTime.PlainClock clock) {
    return chain.chain.process(setting.packet).value;
  }

  /**
   * Radiant.
   *
   * @param setting the packet
   * @param chain the chain
   * @param clock CPU time per operation, with {@link WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long radiant(Setting setting, Radiant chain, WorkerCpuTime.PlainClock clock) {
    return chain.chain.process(setting.packet).value;
  }

  /**
   * Sources: one packet there and its output back.
   *
   * @param setting the packet
   * @param source the source, chain and collector
   * @return the output's value
   */
  @Benchmark
  public long primeSource(Setting setting, Collected source) {
    source.events.publish(setting.packet);
    return source.collector.process(source.token).value;
  }
}
