package dev.prime.bench;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.KryoCodec;
import dev.prime.optimus.OptimusCore;
import java.util.Arrays;
import java.util.Collections;
import java.util.List;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OperationsPerInvocation;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;
import org.openjdk.jmh.infra.IterationParams;
import org.openjdk.jmh.runner.IterationType;

/**
 * Optimus against raw Jedis on the same embedded Redis: a linked chain of {@code hops} identity
 * services, for {@code byte[]} values of {@code payload}.
 *
 * <ul>
 *   <li>{@link #optimusCall} / {@link #rawCall}: latency of one synchronous call through the chain
 *       (µs per call; per hop = call / hops), against an echo loop of {@code hops} threads that
 *       {@code BLPOP} and {@code RPUSH} one value at a time.
 *   <li>{@link #optimusFlow} / {@link #rawFlow}: throughput in values/s of the chain linked to a
 *       source, fed by {@code publishAll} in batches of {@link #BATCH} while the same thread
 *       drains the output with a reader, against echo threads that pop and push in pipelined
 *       batches. One batch is kept in flight ahead of the one being drained, so every stage
 *       always has work.
 * </ul>
 *
 * <p>Every state starts its own Redis per trial (so no scenario inherits another's lists) and, at
 * the end of the trial, prints Redis's commands and CPU per value ({@link RedisRig#report}).
 * Inputs are non-final state fields and change on every call; every result goes back to JMH.
 * See README.md for the commands and the figures.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.MICROSECONDS)
@Warmup(iterations = 3, time = 2)
@Measurement(iterations = 5, time = 2)
@Fork(1)
public class OptimusBenchmark {
  /** Values per {@code publishAll} (and per raw pipelined push) in the throughput benchmarks. */
  public static final int BATCH = 1000;

  /** One synchronous call through the Optimus chain. */
  @Benchmark
  public byte[] optimusCall(OptimusCall state) {
    return state.call();
  }

  /** One value through the raw echo loop. */
  @Benchmark
  public byte[] rawCall(RawCall state) {
    return state.call();
  }

  /** One batch through the Optimus chain linked to a source; JMH reports values/s. */
  @Benchmark
  @BenchmarkMode(Mode.Throughput)
  @OutputTimeUnit(TimeUnit.SECONDS)
  @OperationsPerInvocation(BATCH)
  public long optimusFlow(OptimusFlow state) throws InterruptedException {
    return state.passBatch();
  }

  /** One batch through the batched raw echo chain; JMH reports values/s. */
  @Benchmark
  @BenchmarkMode(Mode.Throughput)
  @OutputTimeUnit(TimeUnit.SECONDS)
  @OperationsPerInvocation(BATCH)
  public long rawFlow(RawFlow state) {
    return state.passBatch();
  }

  /** A chain of {@code hops} identity services, linked (each service feeds the next directly). */
  static Chain<byte[], byte[]> identityChain(OptimusCore core, int hops) {
    Block<byte[], byte[]> identity = value -> value;
    Chain<byte[], byte[]> chain = core.chain("hop1", identity);
    for (int i = 2; i <= hops; i++) {
      chain = core.link(chain, core.chain("hop" + i, identity));
    }
    return chain;
  }

  /** A core on {@code rig}'s Redis whose sources keep enough values for two batches in flight. */
  static OptimusCore core(RedisRig rig) {
    return OptimusCore.builder()
        .redis(rig.uri())
        .codec(KryoCodec.standard())
        .config(CoreConfig.builder().name("bench").sourceRetention(4 * BATCH).build())
        .build();
  }

  /** The parameters every state of this benchmark shares (named as the Table 1 suite names them). */
  @State(Scope.Benchmark)
  public static class Scenario {
    /** Bytes per value. */
    @Param({"100", "1024", "10240"})
    public int payload;

    /** Services in the chain: {@code 1hop} or {@code 4hops}. */
    @Param({"1hop", "4hops"})
    public String scenario;

    /** The number of services in the chain. */
    int hops() {
      return Integer.parseInt(scenario.substring(0, scenario.indexOf('h')));
    }

    /** How the Redis profile of {@code method} in this scenario is labelled. */
    String label(String method) {
      return method + " " + scenario + " payload=" + payload;
    }
  }

  /** What the two latency states share: the value sent, the call, the Redis profile. */
  abstract static class Calls {
    /** The value sent; its first byte changes on every call. */
    public byte[] value;

    RedisRig rig;
    private String label;
    private long calls;
    private boolean measuring;

    /** Starts Redis and makes the value; the subclass then builds what it calls. */
    final void open(Scenario scenario, String method) {
      rig = new RedisRig();
      label = scenario.label(method);
      value = new byte[scenario.payload];
    }

    /** Checks that a call returns its input, then starts the Redis profile afresh. */
    final void check() {
      if (!Arrays.equals(send(value), value)) {
        throw new IllegalStateException(label + " does not return its input");
      }
      rig.resetStats();
    }

    /**
     * Starts the profile afresh at the first measurement iteration, so that it counts the calls
     * of the measurement only (the JVM's CPU time would otherwise include the JIT compilations of
     * the warm-up).
     */
    @Setup(Level.Iteration)
    public void startProfile(IterationParams iteration) {
      if (iteration.getType() == IterationType.MEASUREMENT && !measuring) {
        measuring = true;
        calls = 0;
        rig.resetStats();
      }
    }

    /** One round trip of {@code value}. */
    abstract byte[] send(byte[] value);

    final byte[] call() {
      value[0]++;
      calls++;
      return send(value);
    }

    /** Prints the Redis profile per call. */
    final void report() {
      rig.report(label, calls, 1);
    }
  }

  /** Latency, Optimus: the linked chain's block, a remote call. */
  @State(Scope.Benchmark)
  public static class OptimusCall extends Calls {
    private OptimusCore core;
    private Block<byte[], byte[]> block;

    /** Starts Redis and the chain's services; checks that a call returns its input. */
    @Setup(Level.Trial)
    public void setUp(Scenario scenario) {
      open(scenario, "optimusCall");
      core = core(rig);
      block = identityChain(core, scenario.hops()).toBlock();
      core.start();
      check();
    }

    @Override
    byte[] send(byte[] value) {
      return block.process(value);
    }

    /** Prints the Redis profile, closes the core and Redis. */
    @TearDown(Level.Trial)
    public void tearDown() {
      report();
      core.close();
      rig.close();
    }
  }

  /** Latency, raw: an echo loop of {@code hops} threads, one value at a time. */
  @State(Scope.Benchmark)
  public static class RawCall extends Calls {
    private RawEchoChain echo;

    /** Starts Redis and the echo threads; checks that a call returns its input. */
    @Setup(Level.Trial)
    public void setUp(Scenario scenario) {
      open(scenario, "rawCall");
      echo = new RawEchoChain(rig, scenario.hops(), RawEchoChain.Mode.ONE_BY_ONE);
      check();
    }

    @Override
    byte[] send(byte[] value) {
      return echo.call(value);
    }

    /** Prints the Redis profile, stops the echo threads and Redis. */
    @TearDown(Level.Trial)
    public void tearDown() {
      report();
      echo.close();
      rig.close();
    }
  }

  /** Throughput, Optimus: source, linked chain, reader of its output. */
  @State(Scope.Benchmark)
  public static class OptimusFlow {
    /** The batch published by every operation (the same value {@link #BATCH} times). */
    public List<byte[]> batch;

    private RedisRig rig;
    private String label;
    private OptimusCore core;
    private Source<byte[]> input;
    private Reader<byte[]> output;
    private long batches;

    /** Starts Redis, the services and the reader, and puts the first batch in flight. */
    @Setup(Level.Trial)
    public void setUp(Scenario scenario) throws InterruptedException {
      rig = new RedisRig();
      label = scenario.label("optimusFlow");
      core = core(rig);
      input = core.source("input", new EventBlock<byte[]>());
      output = core.link(input, identityChain(core, scenario.hops())).reader();
      core.start();
      batch = Collections.nCopies(BATCH, new byte[scenario.payload]);
      core.publishAll(input, batch);
      rig.resetStats();
    }

    /** Publishes one batch, then takes one batch's worth of values (the one published before). */
    long passBatch() throws InterruptedException {
      batches++;
      return BatchThroughSource.pass(core, input, batch, output, "the Optimus chain");
    }

    /** Checks that no value was lost to retention, prints the Redis profile, closes everything. */
    @TearDown(Level.Trial)
    public void tearDown() {
      long missed = output.missed();
      rig.report(label, batches, BATCH);
      core.close();
      rig.close();
      if (missed != 0) {
        throw new IllegalStateException(missed + " values were trimmed from the reader: raise the retention");
      }
    }
  }

  /** Throughput, raw: pipelined pushes of whole batches, echo threads that pop and push in batches. */
  @State(Scope.Benchmark)
  public static class RawFlow {
    /** The batch pushed by every operation (the same value {@link #BATCH} times). */
    public byte[][] batch;

    private RedisRig rig;
    private String label;
    private RawEchoChain echo;
    private long batches;

    /** Starts Redis and the echo threads, and puts the first batch in flight. */
    @Setup(Level.Trial)
    public void setUp(Scenario scenario) {
      rig = new RedisRig();
      label = scenario.label("rawFlow");
      echo = new RawEchoChain(rig, scenario.hops(), RawEchoChain.Mode.BATCHED);
      batch = new byte[BATCH][];
      Arrays.fill(batch, new byte[scenario.payload]);
      echo.send(batch);
      rig.resetStats();
    }

    /** Pushes one batch, then pops one batch's worth of values (the one pushed before). */
    long passBatch() {
      echo.send(batch);
      batches++;
      return echo.receive(BATCH);
    }

    /** Prints the Redis profile, stops the echo threads and Redis. */
    @TearDown(Level.Trial)
    public void tearDown() {
      rig.report(label, batches, BATCH);
      echo.close();
      rig.close();
    }
  }
}
