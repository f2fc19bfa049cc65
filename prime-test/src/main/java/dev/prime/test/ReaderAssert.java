package dev.prime.test;

import dev.prime.CoreClosedException;
import dev.prime.Reader;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import java.util.Objects;
import java.util.Optional;
import java.util.function.Consumer;
import java.util.function.Predicate;
import org.opentest4j.AssertionFailedError;

/**
 * Assertions on what a {@link Reader} emits, step by step, in the spirit of Reactor's {@code
 * StepVerifier}. Each step runs when it is called: it takes values from the reader (waiting with
 * {@link Reader#take(Duration)}, never sleeping) and fails at once with a message that says what
 * was expected, what came, and after how long.
 *
 * <pre>{@code
 * ReaderAssert.assertThat(doubled)
 *     .within(Duration.ofSeconds(2))        // each following step must be met within 2 s
 *     .emits(2, 4)                          // the next two values, in order
 *     .emitsMatching("even", x -> x % 2 == 0)
 *     .emitsNothingWithin(Duration.ofMillis(100));
 * core.close();
 * ReaderAssert.assertThat(doubled).completes(); // the reader ends when its core closes
 * }</pre>
 *
 * <p>A reader ends when its core is closed: every read then throws {@link CoreClosedException},
 * even if values were left unread. {@link #completes()} expects that; any other step that meets
 * it fails, saying the reader completed.
 *
 * <p>Values a step takes are gone from the reader, as with any read. Not thread-safe: use one
 * {@code ReaderAssert} from one thread.
 *
 * @param <T> type of the values
 */
public final class ReaderAssert<T> {

  /** How long each step waits unless {@link #within(Duration)} says otherwise: 10 s. */
  public static final Duration DEFAULT_TIMEOUT = Duration.ofSeconds(10);

  /** The longest wait a step's deadline is reckoned with (about 146 years): it cannot overflow. */
  private static final long LONGEST_NANOS = Long.MAX_VALUE / 2;

  private static final int HISTORY_SHOWN = 20;
  private static final int VALUE_CHARS = 200;

  private final Reader<T> reader;
  private final List<T> taken = new ArrayList<>();
  private Duration timeout = DEFAULT_TIMEOUT;

  private ReaderAssert(Reader<T> reader) {
    this.reader = Objects.requireNonNull(reader, "reader must not be null");
  }

  /**
   * Starts assertions on {@code reader}.
   *
   * @param reader the reader to take values from
   * @param <T> type of the values
   * @return the assertions, each step waiting at most {@link #DEFAULT_TIMEOUT}
   */
  public static <T> ReaderAssert<T> assertThat(Reader<T> reader) {
    return new ReaderAssert<>(reader);
  }

  /**
   * Sets how long each following step may take, counted from the moment it is called: {@code
   * emits(a, b, c)} must see all three values within it.
   *
   * @param timeout zero (only values already there count) or positive
   * @return this
   */
  public ReaderAssert<T> within(Duration timeout) {
    Objects.requireNonNull(timeout, "timeout must not be null");
    if (timeout.isNegative()) {
      throw new IllegalArgumentException("timeout must be zero or positive, was " + timeout);
    }
    this.timeout = timeout;
    return this;
  }

  /**
   * Expects the next values to be {@code expected}, in this order ({@link Objects#equals}).
   *
   * @param expected the values
   * @return this
   * @throws AssertionFailedError if another value comes, or not all come in time
   */
  @SafeVarargs
  public final ReaderAssert<T> emits(T... expected) {
    Objects.requireNonNull(expected, "expected values must not be null");
    List<T> values = new ArrayList<>(expected.length);
    for (T value : expected) {
      values.add(value);
    }
    return emitsAll(values);
  }

  /**
   * Expects the next values to be {@code expected}, in this order ({@link Objects#equals}).
   *
   * @param expected the values
   * @return this
   * @throws AssertionFailedError if another value comes, or not all come in time
   */
  public ReaderAssert<T> emitsAll(List<? extends T> expected) {
    Objects.requireNonNull(expected, "expected values must not be null");
    long start = System.nanoTime();
    for (int i = 0; i < expected.size(); i++) {
      T want = expected.get(i);
      String step = expected.size() == 1
          ? "value " + show(want)
          : "value " + (i + 1) + " of " + show(expected) + ", " + show(want) + ",";
      T got = next(step, start);
      if (!Objects.equals(want, got)) {
        throw new AssertionFailedError(
            "expected " + step + " but got " + show(got) + " after " + since(start)
                + history(), want, got);
      }
    }
    return this;
  }

  /**
   * Expects the next value to satisfy {@code condition}.
   *
   * @param condition what the value must satisfy
   * @return this
   * @throws AssertionFailedError if the value does not, or none comes in time
   */
  public ReaderAssert<T> emitsMatching(Predicate<? super T> condition) {
    return emitsMatching("a value matching the condition", condition);
  }

  /**
   * Expects the next value to satisfy {@code condition}, described in failure messages.
   *
   * @param description what the condition asks, e.g. {@code "a pose within 5 cm of the goal"}
   * @param condition what the value must satisfy
   * @return this
   * @throws AssertionFailedError if the value does not, or none comes in time
   */
  public ReaderAssert<T> emitsMatching(String description, Predicate<? super T> condition) {
    Objects.requireNonNull(condition, "condition must not be null");
    long start = System.nanoTime();
    String step = description + " (" + ordinal() + ")";
    T got = next(step, start);
    if (!condition.test(got)) {
      throw new AssertionFailedError(
          "expected " + step + " but got " + show(got) + ", which does not match, after "
              + since(start) + history());
    }
    return this;
  }

  /**
   * Expects a next value and hands it to {@code assertions}, whose failures are reported with what
   * the reader emitted so far.
   *
   * @param assertions assertions on the value, e.g. {@code v -> assertEquals(2, v.x())}
   * @return this
   * @throws AssertionError if the assertions fail, or no value comes in time
   */
  public ReaderAssert<T> emitsSatisfying(Consumer<? super T> assertions) {
    Objects.requireNonNull(assertions, "assertions must not be null");
    long start = System.nanoTime();
    String step = "a value (" + ordinal() + ")";
    T got = next(step, start);
    try {
      assertions.accept(got);
    } catch (AssertionError e) {
      throw new AssertionFailedError(
          "value " + show(got) + " (" + ordinal(taken.size()) + ", after " + since(start)
              + ") failed: " + e.getMessage() + history(), e);
    }
    return this;
  }

  /**
   * Expects {@code count} more values, whatever they are.
   *
   * @param count how many, zero or more
   * @return this
   * @throws AssertionFailedError if fewer come in time
   */
  public ReaderAssert<T> emitsCount(int count) {
    if (count < 0) {
      throw new IllegalArgumentException("count must be zero or more, was " + count);
    }
    long start = System.nanoTime();
    for (int i = 0; i < count; i++) {
      next("value " + (i + 1) + " of " + count + " more", start);
    }
    return this;
  }

  /**
   * Takes values until one satisfies {@code condition} (that one included), all within the
   * timeout.
   *
   * @param description what the condition asks, for failure messages
   * @param condition the value to wait for
   * @return this
   * @throws AssertionFailedError if no such value comes in time
   */
  public ReaderAssert<T> skipsUntil(String description, Predicate<? super T> condition) {
    Objects.requireNonNull(condition, "condition must not be null");
    long start = System.nanoTime();
    int skipped = 0;
    while (true) {
      T got = next(description + " (after " + skipped + " values that did not match)", start);
      if (condition.test(got)) {
        return this;
      }
      skipped++;
    }
  }

  /**
   * Expects the reader to emit nothing for {@code quiet}, and not to complete; waits all of it.
   * The timeout of {@link #within(Duration)} does not apply.
   *
   * @param quiet how long nothing may come: zero (no value is there now) or positive
   * @return this
   * @throws AssertionFailedError if a value comes or the reader completes
   * @throws IllegalArgumentException if {@code quiet} is negative
   */
  public ReaderAssert<T> emitsNothingWithin(Duration quiet) {
    Objects.requireNonNull(quiet, "quiet must not be null");
    if (quiet.isNegative()) {
      throw new IllegalArgumentException("quiet must be zero or positive, was " + quiet);
    }
    long start = System.nanoTime();
    Optional<T> got;
    try {
      got = reader.take(quiet);
    } catch (CoreClosedException e) {
      throw new AssertionFailedError(
          "expected no value within " + show(quiet) + " but the reader completed (its core"
              + " closed) after " + since(start) + "; expect that with completes()" + history(), e);
    } catch (InterruptedException e) {
      throw interrupted("no value within " + show(quiet), start, e);
    }
    if (got.isPresent()) {
      taken.add(got.get());
      throw new AssertionFailedError(
          "expected no value within " + show(quiet) + " but got " + show(got.get()) + " after "
              + since(start) + history());
    }
    return this;
  }

  /**
   * Expects the reader to end (its core closes) within the timeout, with no value before.
   *
   * @throws AssertionFailedError if a value comes, or the reader has not ended in time
   */
  public void completes() {
    long start = System.nanoTime();
    long deadline = deadline(start);
    try {
      Optional<T> got = reader.take(Duration.ofNanos(Math.max(0, deadline - System.nanoTime())));
      if (got.isPresent()) {
        taken.add(got.get());
        throw new AssertionFailedError(
            "expected the reader to complete (its core to close) but got " + show(got.get())
                + " after " + since(start) + history());
      }
    } catch (CoreClosedException e) {
      return;
    } catch (InterruptedException e) {
      throw interrupted("the reader to complete", start, e);
    }
    throw new AssertionFailedError(
        "expected the reader to complete (its core to close) within " + show(timeout)
            + " but it neither completed nor emitted; waited " + since(start) + history());
  }

  /** {@return the values the steps took so far, oldest first} */
  public List<T> taken() {
    return List.copyOf(taken);
  }

  /** The next value, or a failure saying what {@code step} waited for. */
  private T next(String step, long start) {
    long deadline = deadline(start);
    Optional<T> got;
    try {
      got = reader.take(Duration.ofNanos(Math.max(0, deadline - System.nanoTime())));
    } catch (CoreClosedException e) {
      throw new AssertionFailedError(
          "expected " + step + " but the reader completed (its core closed) after " + since(start)
              + history(), e);
    } catch (InterruptedException e) {
      throw interrupted(step, start, e);
    }
    if (got.isEmpty()) {
      throw new AssertionFailedError(
          "expected " + step + " within " + show(timeout) + " but no value came; waited "
              + since(start) + history());
    }
    taken.add(got.get());
    return got.get();
  }

  /**
   * When a step begun at {@code start} times out; a timeout past Long.MAX_VALUE / 2 ns (about 146
   * years) counts as that, so that the deadline does not overflow. (Core's own cap is internal to
   * the core and Optimus, whose module boundary the extension stays outside.)
   */
  private long deadline(long start) {
    return start
        + (timeout.compareTo(Duration.ofNanos(LONGEST_NANOS)) >= 0 ? LONGEST_NANOS : timeout.toNanos());
  }

  private AssertionFailedError interrupted(String step, long start, InterruptedException e) {
    Thread.currentThread().interrupt();
    return new AssertionFailedError(
        "interrupted after " + since(start) + " while waiting for " + step + history(), e);
  }

  private String ordinal() {
    return ordinal(taken.size() + 1);
  }

  private static String ordinal(int n) {
    return "value " + n + " taken by this assertion";
  }

  private String history() {
    if (taken.isEmpty()) {
      return " (no value taken before)";
    }
    int from = Math.max(0, taken.size() - HISTORY_SHOWN);
    StringBuilder out = new StringBuilder(" (values taken by this assertion: ");
    if (from > 0) {
      out.append(from).append(" more, then ");
    }
    List<String> shown = new ArrayList<>();
    for (T value : taken.subList(from, taken.size())) {
      shown.add(show(value));
    }
    return out.append(shown).append(')').toString();
  }

  private static String since(long start) {
    return show(Duration.ofNanos(System.nanoTime() - start));
  }

  private static String show(Duration d) {
    if (d.getSeconds() < 1) {
      return d.toMillis() + " ms";
    }
    if (d.getSeconds() >= 1_000_000) {
      return d.getSeconds() + " s";
    }
    return String.format(Locale.ROOT, "%.1f s", d.getSeconds() + d.getNano() / 1e9);
  }

  private static String show(Object value) {
    String text = String.valueOf(value);
    return text.length() <= VALUE_CHARS ? text : text.substring(0, VALUE_CHARS) + "...";
  }
}
