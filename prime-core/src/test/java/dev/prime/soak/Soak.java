package dev.prime.soak;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.conformance.ConformanceBase;
import java.lang.ref.WeakReference;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.function.Consumer;
import java.util.function.LongSupplier;
import java.util.function.Supplier;

/**
 * Topologies for tests that open and close cores many times, or run many services in one core,
 * shared by the media modules (like the conformance kit, through prime-core's test-jar).
 */
public final class Soak {
  /** How long one value or one close may take before a run fails. */
  public static final Duration PATIENCE = Duration.ofSeconds(20);

  private Soak() {}

  /**
   * One open/close cycle on {@code core} (not started): an event source, two chains linked to it,
   * a reader of the first and a listener of the second, and one synchronous call; starts it,
   * publishes {@code values} values, checks that each arrives once, in order, on both, and that
   * the call returns, then closes the core.
   */
  public static void cycle(PrimeCore core, int values) throws InterruptedException {
    try (core) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("events", events);
      Reader<Integer> plusOne = source.then(core.chain("plus-one", (Integer x) -> x + 1)).reader();
      CountDownLatch doubled = new CountDownLatch(values);
      AtomicInteger nextDoubled = new AtomicInteger();
      List<String> wrong = new ArrayList<>();
      source
          .then(core.chain("doubled", (Integer x) -> 2 * x))
          .listen(
              x -> {
                if (x != 2 * nextDoubled.getAndIncrement()) {
                  synchronized (wrong) {
                    wrong.add("doubled " + x);
                  }
                }
                doubled.countDown();
              });
      Block<Integer, Integer> call = core.chain("call", (Integer x) -> x * 3).toBlock();
      core.start();
      for (int i = 0; i < values; i++) {
        events.publish(i);
      }
      for (int i = 0; i < values; i++) {
        assertEquals(Optional.of(i + 1), plusOne.take(PATIENCE), "value " + i + " read");
      }
      assertTrue(doubled.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS), "every value doubled");
      assertEquals(List.of(), wrong, "doubled values out of order");
      assertEquals(21, call.process(7), "the synchronous call");
    }
  }

  /**
   * Opens a core of {@code cores}, runs {@link #cycle} on it, {@code times} times.
   *
   * @return a weak reference to each core, for {@link Footprint#assertCollected}
   */
  public static List<WeakReference<PrimeCore>> cycles(
      Supplier<? extends PrimeCore> cores, int times, int values) throws InterruptedException {
    List<WeakReference<PrimeCore>> closed = new ArrayList<>();
    for (int i = 0; i < times; i++) {
      PrimeCore core = cores.get();
      closed.add(new WeakReference<>(core));
      cycle(core, values);
    }
    return closed;
  }

  /**
   * One {@link #fanOut} or {@link #line} run: its services, the time {@code start()} took, the time
   * from the first publish until every value arrived, and the time {@code close()} took, in ms;
   * the core's {@code prime-} threads and the caller's reading while it ran.
   */
  public record Timing(
      int services, long startMs, long deliverMs, long closeMs, int primeThreads, long during) {}

  /**
   * {@code chains} chains each linked to one event source (a fan-out), each read by a listener:
   * starts the core, publishes {@code values} values, checks every chain got each once and in
   * order, and closes it.
   *
   * @param during read once while the core runs, after every value arrived (say, Redis's connected
   *     clients); its reading is {@link Timing#during()}
   * @return the times taken and the core's {@code prime-} threads while it ran
   */
  public static Timing fanOut(PrimeCore core, int chains, int values, LongSupplier during)
      throws InterruptedException {
    EventBlock<Integer> events = new EventBlock<>();
    Source<Integer> source = core.source("events", events);
    CountDownLatch all = new CountDownLatch(chains * values);
    AtomicInteger disorder = new AtomicInteger();
    for (int c = 0; c < chains; c++) {
      source.then(core.chain("fan-" + c, (Integer x) -> x)).listen(inOrder(0, all, disorder));
    }
    return run(core, events, values, all, disorder, chains, during);
  }

  /**
   * A line of {@code chains} chains, each adding one, linked one after another and to one event
   * source, read by a listener: starts the core, publishes {@code values} values, checks each
   * arrives once, in order, plus {@code chains}, and closes the core.
   *
   * @param during read once while the core runs, after every value arrived; its reading is
   *     {@link Timing#during()}
   * @return the times taken and the core's {@code prime-} threads while it ran
   */
  public static Timing line(PrimeCore core, int chains, int values, LongSupplier during)
      throws InterruptedException {
    EventBlock<Integer> events = new EventBlock<>();
    Source<Integer> source = core.source("events", events);
    dev.prime.Chain<Integer, Integer> line = core.chain("line-0", (Integer x) -> x + 1);
    for (int c = 1; c < chains; c++) {
      line = line.then(core.chain("line-" + c, (Integer x) -> x + 1));
    }
    CountDownLatch all = new CountDownLatch(values);
    AtomicInteger disorder = new AtomicInteger();
    source.then(line).listen(inOrder(chains, all, disorder));
    return run(core, events, values, all, disorder, chains, during);
  }

  /**
   * A listener expecting {@code first}, {@code first + 1}, ...: counts each value down on {@code
   * all}, and one that is not the next expected on {@code disorder}.
   */
  private static Consumer<Integer> inOrder(int first, CountDownLatch all, AtomicInteger disorder) {
    int[] next = {first};
    return x -> {
      if (x != next[0]++) {
        disorder.incrementAndGet();
      }
      all.countDown();
    };
  }

  private static Timing run(
      PrimeCore core,
      EventBlock<Integer> events,
      int values,
      CountDownLatch all,
      AtomicInteger disorder,
      int chains,
      LongSupplier during)
      throws InterruptedException {
    long startMs;
    long deliverMs;
    int threads;
    long reading;
    try {
      long starting = System.nanoTime();
      core.start();
      startMs = (System.nanoTime() - starting) / 1_000_000;
      long publishing = System.nanoTime();
      for (int i = 0; i < values; i++) {
        events.publish(i);
      }
      assertTrue(
          all.await(PATIENCE.toMillis() * 3, TimeUnit.MILLISECONDS),
          "every value reached every listener: " + all.getCount() + " missing");
      deliverMs = (System.nanoTime() - publishing) / 1_000_000;
      assertEquals(0, disorder.get(), "values out of order or duplicated");
      threads = ConformanceBase.threadsOf(core).size();
      reading = during.getAsLong();
    } catch (Throwable t) {
      core.close();
      throw t;
    }
    long closing = System.nanoTime();
    core.close();
    long closeMs = (System.nanoTime() - closing) / 1_000_000;
    return new Timing(chains, startMs, deliverMs, closeMs, threads, reading);
  }
}
