package dev.prime.bench;

import java.lang.invoke.MethodHandles;
import java.lang.invoke.VarHandle;
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
import org.openjdk.jmh.annotations.Threads;
import org.openjdk.jmh.annotations.Warmup;

/**
 * The machine's floor under every thread hand-off: one round trip of a number between two
 * threads that never sleep (the benchmark thread writes it, an echo thread spinning on it writes
 * it back), nothing else. No library is involved, so what moves this figure from fork to fork is
 * the machine: where the two threads' cores are, and how far apart, at that moment. {@code
 * roundTripWithPacket} is the same round trip doing the synchronous row's work on the row's packet
 * ({@link PacketEcho}): the floor under {@link SyncSourceBenchmark}.
 *
 * <p>Design: the number and its echo are padded 128 bytes apart (their own cache lines,
 * which an adjacent-line prefetch does not pair), written with release and read with acquire; a
 * round trip is two cache-line transfers. The echo thread is a daemon, started per trial and
 * stopped (and joined) at its end. A round trip that does not come back within {@link
 * #TIMEOUT_NANOS} fails the benchmark instead of hanging it.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 3, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(5)
@Threads(1)
public class CoreRoundTripBenchmark {
  /** How long one round trip may take before the benchmark fails: 10 s. */
  static final long TIMEOUT_NANOS = TimeUnit.SECONDS.toNanos(10);

  /** Spin rounds between two reads of the clock while waiting for the echo. */
  private static final int ROUNDS_PER_CLOCK_READ = 1 << 12;

  /** The number, its echo, and the thread that echoes it. */
  @State(Scope.Thread)
  public static class Echo {
    private static final VarHandle SENT;
    private static final VarHandle ECHOED;

    static {
      try {
        MethodHandles.Lookup lookup = MethodHandles.lookup();
        SENT = lookup.findVarHandle(Echo.class, "sent", long.class);
        ECHOED = lookup.findVarHandle(Echo.class, "echoed", long.class);
      } catch (ReflectiveOperationException e) {
        throw new ExceptionInInitializerError(e);
      }
    }

    @SuppressWarnings("unused") // padding: keeps sent and echoed on cache lines of their own
    private long p01, p02, p03, p04, p05, p06, p07, p08, p09, p10, p11, p12, p13, p14, p15, p16;

    private long sent;

    @SuppressWarnings("unused")
    private long q01, q02, q03, q04, q05, q06, q07, q08, q09, q10, q11, q12, q13, q14, q15, q16;

    private long echoed;

    @SuppressWarnings("unused")
    private long r01, r02, r03, r04, r05, r06, r07, r08, r09, r10, r11, r12, r13, r14, r15, r16;

    private volatile boolean running;
    private Thread echo;
    private long next;

    /** Starts the echo thread. */
    @Setup(Level.Trial)
    public void start() {
      running = true;
      long lastSent = next; // read here, not by the echo thread: the first number may be sent before it runs
      echo = new Thread(() -> echoUntilStopped(lastSent), "core-round-trip-echo");
      echo.setDaemon(true);
      echo.start();
    }

    /**
     * Stops the echo thread and waits for it to end.
     *
     * @throws InterruptedException if interrupted while waiting
     */
    @TearDown(Level.Trial)
    public void stop() throws InterruptedException {
      running = false;
      echo.join(TimeUnit.SECONDS.toMillis(10));
    }

    /**
     * Whether the echo thread is still running (after {@link #stop}: it did not end).
     *
     * @return whether it is alive
     */
    public boolean echoing() {
      return echo.isAlive();
    }

    private void echoUntilStopped(long lastSent) {
      long seen = lastSent;
      int rounds = 0;
      while (true) {
        long value = (long) SENT.getAcquire(this);
        if (value != seen) {
          seen = value;
          work();
          ECHOED.setRelease(this, value);
        } else if (++rounds == ROUNDS_PER_CLOCK_READ) {
          rounds = 0;
          if (!running) {
            return;
          }
        } else {
          Thread.onSpinWait();
        }
      }
    }

    /** What the echo thread does between seeing a number and echoing it: nothing here. */
    void work() {}

    /**
     * Sends the next number and waits for its echo.
     *
     * @return the number echoed
     * @throws IllegalStateException if no echo came within {@link #TIMEOUT_NANOS}
     */
    public long roundTrip() {
      long value = ++next;
      SENT.setRelease(this, value);
      int rounds = 0;
      long deadline = 0;
      while ((long) ECHOED.getAcquire(this) != value) {
        Thread.onSpinWait();
        if (++rounds == ROUNDS_PER_CLOCK_READ) {
          rounds = 0;
          long now = System.nanoTime();
          if (deadline == 0) {
            deadline = now + TIMEOUT_NANOS;
          } else if (now - deadline > 0) {
            throw new IllegalStateException(
                "no echo of " + value + " within 10 s: the echo thread "
                    + (echo.isAlive() ? "is starved" : "has ended"));
          }
        }
      }
      return value;
    }
  }

  /**
   * The floor under the synchronous row ({@link SyncSourceBenchmark}): the round trip of {@link
   * Echo}, with the echo thread also running the row's four adders on the row's packet before it
   * answers, and the benchmark thread reading the packet's value after the answer. As in the row,
   * the packet is one object that both threads use in turn, and the adders change it: its cache
   * line moves to the echo thread and back at every round trip, as the two numbers' lines do.
   * Nothing else moves: a library that runs the chain on its own thread adds its queues' slots
   * and indexes to this, so the row is not to be expected faster than this figure on the same
   * machine at the same moment.
   */
  @State(Scope.Thread)
  public static class PacketEcho extends Echo {
    private final PacketBlocks.Add[] adders = ChainShapes.directAdders(4);
    private final Packet packet = Packet.ofSize(100);

    @Override
    void work() {
      ChainShapes.runDirect(adders, packet);
    }

    /**
     * Sends the packet to the echo thread and waits for it to come back.
     *
     * @return the packet's value after the echo thread's adders
     */
    public long packetRoundTrip() {
      roundTrip();
      return packet.value;
    }
  }

  /**
   * One round trip between the two threads.
   *
   * @param echo the number, its echo and the echo thread
   * @return the number echoed
   */
  @Benchmark
  public long roundTrip(Echo echo) {
    return echo.roundTrip();
  }

  /**
   * One round trip between the two threads carrying the synchronous row's packet, which the echo
   * thread runs the row's four adders on: the floor under {@link SyncSourceBenchmark}.
   *
   * @param echo the number, its echo, the packet and the echo thread
   * @return the packet's value
   */
  @Benchmark
  public long roundTripWithPacket(PacketEcho echo) {
    return echo.packetRoundTrip();
  }
}
