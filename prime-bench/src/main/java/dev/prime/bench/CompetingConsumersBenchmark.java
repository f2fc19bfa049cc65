package dev.prime.bench;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.Hosting;
import dev.prime.optimus.KryoCodec;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.Semaphore;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.locks.LockSupport;
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

/**
 * Competing consumers on Optimus (issue 13, item 3): a service whose block takes 1 ms (parked, not
 * spinning: the hosts need no CPU of their own) hosted by 1, 2 or 3 hosts with
 * {@link Hosting#UNORDERED}; throughput in values/s.
 *
 * <ul>
 *   <li>{@link #baseline}: one host with the default {@link Hosting#EXCLUSIVE} (today's single
 *       host: a step takes up to 256 values).
 *   <li>{@link #hosted}: {@code hosts} unordered hosts; {@code hosts=1} is the figure the targets
 *       compare with (2 hosts ≥ 1.8×, 3 hosts ≥ 2.6×).
 * </ul>
 *
 * <p>Each host is an {@link OptimusCore} of its own in this JVM, with the same core name (the same
 * topology) on one embedded Redis per trial: its own connections, threads, instance id, lease and
 * processing list, exactly as a separate process would have them. In-JVM hosts keep forks short and
 * free of three JVMs' start-up and JIT competing for 2 cores; what scales here is the protocol
 * (taking, acknowledging, sharing one input), which is the same across processes. A publishing core
 * (hosting nothing) is fed by {@link #FEEDERS} threads that publish values one by one (one Redis
 * entry each, so they can be shared: a frame goes whole to one host), keeping {@link #IN_FLIGHT}
 * values between publish and output, so the hosts always have work and a publish's round trip is
 * never on the measured path; an operation takes {@link #BATCH} values from a reader of the
 * service's output.
 */
@BenchmarkMode(Mode.Throughput)
@OutputTimeUnit(TimeUnit.SECONDS)
@Warmup(iterations = 2, time = 2)
@Measurement(iterations = 5, time = 2)
@Fork(1)
public class CompetingConsumersBenchmark {
  /** Values taken per operation. */
  public static final int BATCH = 64;

  /** The most values published and not yet taken from the output. */
  static final int IN_FLIGHT = 256;

  /** Threads publishing. */
  static final int FEEDERS = 2;

  /** What the block takes per value. */
  static final long BLOCK_NANOS = 1_000_000;

  private static final Duration TAKE_TIMEOUT = Duration.ofSeconds(30);
  private static final String SERVICE = "slow";

  /** One host, the default exclusive hosting; JMH reports values/s. */
  @Benchmark
  @OperationsPerInvocation(BATCH)
  public long baseline(OneExclusiveHost state) throws InterruptedException {
    return state.passBatch();
  }

  /** {@code hosts} unordered hosts; JMH reports values/s. */
  @Benchmark
  @OperationsPerInvocation(BATCH)
  public long hosted(UnorderedHosts state) throws InterruptedException {
    return state.passBatch();
  }

  /** The block: parks for {@link #BLOCK_NANOS} (a slow device, a remote call), then returns its input. */
  static int slowBlock(int value) {
    long deadline = System.nanoTime() + BLOCK_NANOS;
    for (long left = BLOCK_NANOS; left > 0; left = deadline - System.nanoTime()) {
      LockSupport.parkNanos(left);
    }
    return value;
  }

  /** The hosts, the publisher, the reader, and one batch in flight. */
  abstract static class Rig {
    private RedisRig redis;
    private final List<OptimusCore> hostCores = new ArrayList<>();
    private OptimusCore publisher;
    private EventBlock<Integer> numbers;
    private Reader<Integer> output;
    private final AtomicInteger next = new AtomicInteger();
    private final Semaphore room = new Semaphore(IN_FLIGHT);
    private final List<Thread> feeders = new ArrayList<>();
    private volatile boolean closing;
    private long batches;
    private String label;

    /** Starts Redis, {@code hosts} hosting cores and the publisher, and puts the first batch in flight. */
    final void open(int hosts, Hosting hosting) {
      label = "competing consumers hosts=" + hosts + " " + hosting;
      redis = new RedisRig();
      for (int i = 0; i < hosts; i++) {
        OptimusCore host = core().hosts(SERVICE).hosting(SERVICE, hosting).build();
        hostCores.add(host);
        declare(host, new EventBlock<>());
      }
      publisher = core().hosts(List.of()).build();
      numbers = new EventBlock<>();
      output = declare(publisher, numbers).reader();
      publisher.start();
      hostCores.forEach(OptimusCore::start);
      for (int i = 0; i < FEEDERS; i++) {
        Thread feeder = new Thread(this::feed, "competing-consumers-feeder-" + i);
        feeder.setDaemon(true);
        feeders.add(feeder);
        feeder.start();
      }
      redis.resetStats();
    }

    private OptimusCore.Builder core() {
      return OptimusCore.builder()
          .redis(redis.uri())
          .codec(KryoCodec.standard())
          .leaseTime(Duration.ofSeconds(2))
          .config(CoreConfig.builder().name("consumers").sourceRetention(4 * IN_FLIGHT).build());
    }

    private static Source<Integer> declare(OptimusCore core, EventBlock<Integer> numbers) {
      return core.source("numbers", numbers).then(core.chain(SERVICE, CompetingConsumersBenchmark::slowBlock));
    }

    /** A feeder: publishes a value whenever fewer than {@link #IN_FLIGHT} are on their way. */
    private void feed() {
      try {
        while (!closing) {
          room.acquire();
          numbers.publish(next.getAndIncrement());
        }
      } catch (InterruptedException e) {
        // closing
      } catch (RuntimeException e) {
        if (!closing) {
          throw e;
        }
      }
    }

    /** Takes one batch of values from the output (in whatever order they come), making room for as many. */
    final long passBatch() throws InterruptedException {
      batches++;
      long sum = 0;
      for (int i = 0; i < BATCH; i++) {
        Optional<Integer> value = output.take(TAKE_TIMEOUT);
        if (value.isEmpty()) {
          throw new IllegalStateException("a value did not come through the hosts within " + TAKE_TIMEOUT);
        }
        sum += value.get();
      }
      room.release(BATCH);
      return sum;
    }

    /** Checks that the reader missed nothing, prints the Redis profile, closes everything. */
    final void close() throws InterruptedException {
      closing = true;
      for (Thread feeder : feeders) {
        feeder.interrupt();
        feeder.join(TAKE_TIMEOUT.toMillis());
      }
      long missed = output.missed();
      redis.report(label, batches, BATCH);
      publisher.close();
      hostCores.forEach(OptimusCore::close);
      redis.close();
      if (missed != 0) {
        throw new IllegalStateException(missed + " values were trimmed from the reader: raise the retention");
      }
    }
  }

  /** One host with the default hosting. */
  @State(Scope.Benchmark)
  public static class OneExclusiveHost extends Rig {
    /** Starts the rig. */
    @Setup(Level.Trial)
    public void setUp() {
      open(1, Hosting.EXCLUSIVE);
    }

    /** Closes the rig. */
    @TearDown(Level.Trial)
    public void tearDown() throws InterruptedException {
      close();
    }
  }

  /** {@code hosts} unordered hosts. */
  @State(Scope.Benchmark)
  public static class UnorderedHosts extends Rig {
    /** Cores hosting the service at once. */
    @Param({"1", "2", "3"})
    public int hosts;

    /** Starts the rig. */
    @Setup(Level.Trial)
    public void setUp() {
      open(hosts, Hosting.UNORDERED);
    }

    /** Closes the rig. */
    @TearDown(Level.Trial)
    public void tearDown() throws InterruptedException {
      close();
    }
  }
}
