package dev.prime;

import dev.prime.internal.ServiceThreads;
import dev.prime.internal.RateLimitedLog;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Objects;
import java.util.concurrent.atomic.AtomicReference;
import java.util.function.Function;
import java.util.function.Supplier;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * The combinators of sources and the timers of one core ({@link PrimeCore#combineLatest}, {@link
 * PrimeCore#zip}, {@link PrimeCore#merge}, {@link PrimeCore#timer}, {@link Source#withLatestFrom},
 * {@link Source#sample}), built on what every media has: readers of sources, a source fed by an
 * event block ({@link PrimeCore#newSource}) for the output, and the core's service threads. Each
 * is recorded in the topology as one service, so on a media that spreads services over processes
 * only the process that hosts it runs it.
 *
 * <p>Design note. Declaring checks every argument before it records anything. Timers and samplers
 * are kept in a list until the core starts, when {@link #started()} fixes their origin by the
 * core's clock (so ticks count from {@code start()}, the same on every run); those declared later
 * fix it at once. The list and the started flag share this object's lock.
 */
final class Combinators {
  private static final Logger LOG = LoggerFactory.getLogger(Combinators.class);

  private final PrimeCore core;
  private final ServiceThreads threads;
  private final RateLimitedLog drops = new RateLimitedLog(Combinators.class.getName());
  private final List<Ticking> waiting = new ArrayList<>(); // guarded by this
  private boolean started; // guarded by this

  Combinators(PrimeCore core, ServiceThreads threads) {
    this.core = core;
    this.threads = threads;
  }

  /** Fixes the origin of every timer and sampler declared so far: the core starts. */
  void started() {
    synchronized (this) {
      started = true;
      waiting.forEach(Ticking::begin);
      waiting.clear();
    }
  }

  /** Writes the count of zip drops not yet logged: the core closed, no zip drops any more. */
  void closed() {
    drops.flush();
  }

  <R> Source<R> combineLatest(Function<Object[], Object> tuple, Source<?>... sources) {
    return declared(
        () -> {
          List<Source<?>> inputs = checked(sources);
          String name = core.topologyRecorder().combinator("combineLatest", inputs);
          return combine(name, inputs, Pairing.combineLatest(inputs.size(), tuple));
        });
  }

  <R> Source<R> zip(Function<Object[], Object> tuple, Source<?>... sources) {
    return declared(
        () -> {
          List<Source<?>> inputs = checked(sources);
          String name = core.topologyRecorder().combinator("zip", inputs);
          int limit = core.config().sourceRetention();
          Pairing zip =
              Pairing.zip(
                  inputs.size(),
                  limit,
                  tuple,
                  input ->
                      drops.record(
                          "zip '" + name + "' dropped unpaired values",
                          1,
                          "input " + (input + 1) + " was " + limit + " values ahead",
                          () ->
                              LOG.warn(
                                  "zip '{}' dropped the oldest unpaired value of input {} ({}): it was"
                                      + " {} values ahead of another input (the zip keeps at most"
                                      + " CoreConfig.sourceRetention() unpaired values per input)",
                                  name,
                                  input + 1,
                                  inputs.get(input).name(),
                                  limit)));
          return combine(name, inputs, zip);
        });
  }

  <T> Source<T> merge(Source<?>... sources) {
    return declared(
        () -> {
          List<Source<?>> inputs = checked(sources);
          String name = core.topologyRecorder().combinator("merge", inputs);
          return combine(name, inputs, Pairing.merge());
        });
  }

  <T, U> Source<Tuple2<T, U>> withLatestFrom(Source<T> source, Source<U> latest) {
    return declared(
        () -> {
          List<Source<?>> inputs = checked(source, latest);
          String name = core.topologyRecorder().combinator("withLatestFrom", inputs);
          return combine(name, inputs, Pairing.withLatestFrom());
        });
  }

  <T> Source<T> sample(Source<T> source, Duration period) {
    return declared(
        () -> {
          long nanos = checkedPeriod(period);
          List<Source<?>> inputs = checked(source);
          String name = core.topologyRecorder().combinator("sample", inputs);
          return hosted(
              name,
              () -> {
                EventBlock<Object> events = new EventBlock<>();
                Source<Object> out = core.newSource(name, events);
                AtomicReference<Object> latest = new AtomicReference<>();
                CombinedInputs.run(
                    core,
                    threads,
                    name,
                    inputs,
                    core.model().combinator(name, (input, value) -> latest.set(value)));
                schedule(
                    name + " clock",
                    new Ticking(
                        core,
                        name,
                        nanos,
                        (count, time) -> {
                          Object value = latest.getAndSet(null);
                          if (value != null) {
                            events.publish(value);
                          }
                        }));
                return typed(out);
              });
        });
  }

  Source<Tick> timer(String name, Duration period) {
    return declared(
        () -> {
          Objects.requireNonNull(name, "timer name must not be null");
          long nanos = checkedPeriod(period);
          core.ensureOpen();
          String claimed = core.topologyRecorder().timer(name, period);
          return hosted(
              claimed,
              () -> {
                EventBlock<Tick> events = new EventBlock<>();
                Source<Tick> out = core.newSource(claimed, events);
                schedule(
                    claimed,
                    new Ticking(
                        core, claimed, nanos, (count, time) -> events.publish(new Tick(count, time))));
                return out;
              });
        });
  }

  /**
   * Runs a combinator's or timer's declaration atomically with the core's other declarations:
   * if it throws, the nodes it recorded are forgotten and their names freed.
   */
  private <T> T declared(Supplier<T> declaration) {
    return core.topologyRecorder().declare(declaration);
  }

  private void schedule(String thread, Ticking ticking) {
    synchronized (this) {
      if (started) {
        ticking.begin();
      } else {
        waiting.add(ticking);
      }
    }
    threads.add(thread, ticking);
  }

  /**
   * Takes the hosting of a combinator or timer declared on a started core (before the start,
   * {@code start()} takes it): on a media that spreads services over processes, its host lease;
   * then makes it. If making it fails, the hosting taken is given up again ({@link
   * PrimeCore#unhostOnCoreThreads}): the failed declaration leaves nothing behind.
   */
  private <T> T hosted(String service, Supplier<T> make) {
    boolean hosting = core.isStarted();
    if (hosting) {
      core.hostOnCoreThreads(service);
    }
    try {
      return make.get();
    } catch (RuntimeException | Error failed) {
      if (hosting) {
        core.unhostOnCoreThreads(service);
      }
      throw failed;
    }
  }

  /** The output source of a combinator and its input services. */
  private <R> Source<R> combine(String name, List<Source<?>> inputs, Pairing pairing) {
    return hosted(
        name,
        () -> {
          EventBlock<Object> events = new EventBlock<>();
          Source<Object> out = core.newSource(name, events);
          CombinedInputs.InputStep step =
              (input, value) -> pairing.accept(input, value, events::publish);
          CombinedInputs.run(core, threads, name, inputs, core.model().combinator(name, step));
          return typed(out);
        });
  }

  /** The output source, typed as the combinator's values (which it carries only). */
  @SuppressWarnings({"unchecked", "rawtypes"})
  private static <R> Source<R> typed(Source<Object> out) {
    return (Source<R>) (Source) out;
  }

  private List<Source<?>> checked(Source<?>... sources) {
    Objects.requireNonNull(sources, "sources must not be null");
    if (sources.length == 0) {
      throw new IllegalArgumentException("give at least one source to combine");
    }
    for (int i = 0; i < sources.length; i++) {
      if (sources[i] == null) {
        throw new NullPointerException("source argument " + (i + 1) + " must not be null");
      }
      core.requireSource(sources[i]);
    }
    return List.copyOf(Arrays.asList(sources));
  }

  private static long checkedPeriod(Duration period) {
    Objects.requireNonNull(period, "period must not be null");
    if (period.isNegative() || period.isZero()) {
      throw new IllegalArgumentException("the period must be positive, not " + period);
    }
    try {
      return period.toNanos();
    } catch (ArithmeticException e) {
      throw new IllegalArgumentException("the period " + period + " is too long: at most about 292 years", e);
    }
  }
}
