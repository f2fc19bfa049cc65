package dev.prime.bench;

import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.KryoCodec;
import dev.prime.optimus.LocalRedisCluster;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
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
import redis.clients.jedis.Jedis;

/**
 * What {@code OptimusCore.Builder.replicaAcks} costs on a Redis Cluster: the same one-service
 * topology on a local cluster of 3 masters and 3 replicas ({@code LocalRedisCluster}, from
 * prime-optimus's test-jar; loopback, no persistence), with {@code replicaAcks = 0} (the
 * baseline: no {@code WAIT}) and {@code 1} (every Redis operation of the core waits until the
 * master's replica has it).
 *
 * <ul>
 *   <li>{@link #call}: one synchronous call of an identity service of {@link #PAYLOAD} bytes (µs).
 *   <li>{@link #flow}: throughput in values/s of the identity service linked to a source, fed by
 *       {@code publishAll} in batches of {@link #BATCH} while the same thread drains the output
 *       with a reader; one batch stays in flight ahead of the one drained.
 * </ul>
 *
 * <p>Each trial starts its own cluster (a fork per {@code replicaAcks} value), and at its end
 * prints the commands and CPU per value of the master that holds the topology's slot (the
 * {@code wait} line is what the acks add).
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.MICROSECONDS)
@Warmup(iterations = 3, time = 2)
@Measurement(iterations = 5, time = 2)
@Fork(1)
public class ClusterReplicaAcksBenchmark {
  /** Values per {@code publishAll} in {@link #flow}. */
  public static final int BATCH = 100;

  /** Bytes per value. */
  public static final int PAYLOAD = 100;

  /** One synchronous call through the service. */
  @Benchmark
  public byte[] call(ClusterCall state) {
    return state.call();
  }

  /** One batch through the service linked to a source; JMH reports values/s. */
  @Benchmark
  @BenchmarkMode(Mode.Throughput)
  @OutputTimeUnit(TimeUnit.SECONDS)
  @OperationsPerInvocation(BATCH)
  public long flow(ClusterFlow state) throws InterruptedException {
    return state.passBatch();
  }

  /** The parameter both states share. */
  @State(Scope.Benchmark)
  public static class Acks {
    /** Replicas that confirm every Redis operation: {@code 0} is the baseline (no acks). */
    @Param({"0", "1"})
    public int replicaAcks;
  }

  /** A cluster and a core on it, for one trial; the Redis profile of the topology's master. */
  public abstract static class OnCluster {
    /**
     * A running cluster for the states to use instead of starting one each, and not to close
     * ({@code null}: each trial starts and closes its own); lets a test run several states on one
     * cluster.
     */
    static LocalRedisCluster shared;

    LocalRedisCluster cluster;
    OptimusCore core;
    private String label;
    private LocalRedisCluster.Node master;
    private double cpuAtReset;

    /** Starts the cluster and a core named {@code name} on it, with {@code replicaAcks}. */
    final void open(String name, int replicaAcks) {
      label = name + " replicaAcks=" + replicaAcks;
      // a long node timeout: a node starved of CPU on a loaded machine is not failed over
      cluster = shared != null ? shared : LocalRedisCluster.start(3, Duration.ofSeconds(5), false);
      core = OptimusCore.builder()
          .redis(cluster.getUrl())
          .replicaAcks(replicaAcks)
          .codec(KryoCodec.standard())
          .config(CoreConfig.builder().name(name).sourceRetention(4 * BATCH).build())
          .build();
      master = cluster.masterOfKey("prime:{" + name + "}:");
    }

    /** Forgets the master's statistics so far: call once the topology is set up. */
    final void resetStats() {
      try (Jedis jedis = master.jedis()) {
        jedis.configResetStat();
        cpuAtReset = RedisRig.cpuSeconds(jedis);
      }
    }

    /** How often the topology's master ran {@code command} since {@link #resetStats} ({@code INFO commandstats}). */
    final long masterCalls(String command) {
      try (Jedis jedis = master.jedis()) {
        String prefix = "cmdstat_" + command + ":calls=";
        for (String line : jedis.info("commandstats").split("\r?\n")) {
          if (line.startsWith(prefix)) {
            return Long.parseLong(line.substring(prefix.length(), line.indexOf(',')));
          }
        }
        return 0;
      }
    }

    /** Prints the master's profile per value, closes the core and the cluster. */
    final void close(long operations, int valuesPerOperation) {
      try (Jedis jedis = master.jedis()) {
        RedisRig.report(jedis, cpuAtReset, label, operations, valuesPerOperation);
      } finally {
        core.close();
        if (cluster != shared) {
          cluster.close();
        }
      }
    }
  }

  /** Latency: the identity service's block, a remote call. */
  @State(Scope.Benchmark)
  public static class ClusterCall extends OnCluster {
    /** The value sent; its first byte changes on every call. */
    public byte[] value;

    private Block<byte[], byte[]> block;
    private long calls;

    /** Starts the cluster and the service; checks that a call returns its input. */
    @Setup(Level.Trial)
    public void setUp(Acks acks) {
      open("acks-call", acks.replicaAcks);
      block = core.chain("echo", (Block<byte[], byte[]>) input -> input).toBlock();
      core.start();
      value = new byte[PAYLOAD];
      if (!Arrays.equals(block.process(value), value)) {
        throw new IllegalStateException("the service does not return its input");
      }
      resetStats();
    }

    byte[] call() {
      value[0]++;
      calls++;
      return block.process(value);
    }

    /** Prints the Redis profile, closes the core and the cluster. */
    @TearDown(Level.Trial)
    public void tearDown() {
      close(calls, 1);
    }
  }

  /** Throughput: source, identity service, reader of its output. */
  @State(Scope.Benchmark)
  public static class ClusterFlow extends OnCluster {
    /** The batch published by every operation (the same value {@link #BATCH} times). */
    public List<byte[]> batch;

    private Source<byte[]> input;
    private Reader<byte[]> output;
    private long batches;

    /** Starts the cluster, the service and the reader, and puts the first batch in flight. */
    @Setup(Level.Trial)
    public void setUp(Acks acks) {
      open("acks-flow", acks.replicaAcks);
      input = core.source("input", new EventBlock<byte[]>());
      output = input.then(core.chain("echo", (Block<byte[], byte[]>) value -> value)).reader();
      core.start();
      batch = Collections.nCopies(BATCH, new byte[PAYLOAD]);
      core.publishAll(input, batch);
      resetStats();
    }

    /** Publishes one batch, then takes one batch's worth of values (the one published before). */
    long passBatch() throws InterruptedException {
      batches++;
      return BatchThroughSource.pass(core, input, batch, output, "the service");
    }

    /** Checks that no value was lost to retention, prints the Redis profile, closes everything. */
    @TearDown(Level.Trial)
    public void tearDown() {
      long missed = output.missed();
      close(batches, BATCH);
      if (missed != 0) {
        throw new IllegalStateException(missed + " values were trimmed from the reader: raise the retention");
      }
    }
  }
}
