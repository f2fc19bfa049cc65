package dev.prime;

import dev.prime.internal.Deadlines;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.Collection;
import java.util.Collections;
import java.util.Comparator;
import java.util.LinkedHashMap;
import java.util.LinkedHashSet;
import java.util.List;
import java.util.Map;
import java.util.NoSuchElementException;
import java.util.Objects;
import java.util.Optional;
import java.util.Set;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.atomic.LongAdder;
import java.util.function.BooleanSupplier;

/**
 * What a core recorded: every value each of its sources published and each of its chains made of
 * a block returned, under the source's or chain's name in the topology, with its pseudoname (see
 * {@link PrimeCore#chain(String, String, Block)}), a wall-clock and a monotonic time stamp and a
 * sequence number per name. Get it with {@link PrimeCore#recording()} from a core whose {@link
 * CoreConfig} turns recording on ({@link CoreConfig.Builder#recording(RecordingOptions)}). *
 * <p>Recorded are exactly two kinds of node: every event source ({@link PrimeCore#source(String,
 * EventBlock)}: each value its event block publishes that the media accepted) and every chain made
 * of a block ({@link PrimeCore#chain(String, Block)}: each non-null value its block returns,
 * wherever the media runs it). Nothing else has a name here: filters, flat-maps, listeners,
 * readers, timers, combinators, generic services, templates (if/else, for-each, union, fork,
 * guard...), links and collectors are not recorded; a value they make is recorded only where it
 * comes out of a recorded chain.
 *
 * <p>Reading never consumes: every method returns what the ring of a name holds now, and many
 * readers may read the same values.
 *
 * <ul>
 *   <li>{@link #get(String)}: the latest value; if nothing was recorded under the name yet, waits
 *       for the first one up to {@link RecordingOptions#getTimeout()} ({@link #get(String,
 *       Duration)}: up to a given time), then throws {@link NoSuchElementException}; it does not
 *       wait once the core is closed (nor on a merged recording): nothing more will come;
 *   <li>{@link #tryGet(String)}: the latest value if there is one, never waiting;
 *   <li>{@link #getRange(String, long, long)}: the values numbered {@code from} (inclusive) to
 *       {@code to} (exclusive) that the ring still holds, oldest first; {@link #getAll(String)}:
 *       every value it holds;
 *   <li>the same four with {@code Stamped} give {@link RecordedValue}s: the value with its name,
 *       pseudoname, sequence number and time stamps.
 * </ul>
 *
 * <p>Values are typed by the caller: {@code Estimate e = recording.get("odometry");} (a wrong
 * type fails with {@link ClassCastException} where the value is used). A name that is not
 * recorded throws {@link IllegalArgumentException} listing the names that are. Each name keeps
 * its latest {@link RecordingOptions#capacity()} values; what falls out is counted ({@link
 * #dropped(String)}), and sequence numbers say which values those were.
 *
 * <p>On a media that spreads services over processes (Optimus), each process records what runs
 * in it: the values its event blocks publish and the outputs of the chains it hosts. {@link
 * #merge(Recording...)} joins the recordings of several processes by wall-clock time.
 *
 * <p>Thread-safe.
 */
public final class Recording {
  private final String core;
  private final RecordingOptions options;
  private final Map<String, RecordingRing> rings; // guarded by itself
  private final BooleanSupplier finished; // true: nothing more will be recorded
  private final CopyOnWriteArrayList<Subscription> subscriptions = new CopyOnWriteArrayList<>();

  Recording(String core, RecordingOptions options, BooleanSupplier finished) {
    this(core, options, new LinkedHashMap<>(), finished);
  }

  private Recording(
      String core,
      RecordingOptions options,
      Map<String, RecordingRing> rings,
      BooleanSupplier finished) {
    this.core = core;
    this.options = options;
    this.rings = rings;
    this.finished = finished;
  }

  /** The ring of a name just recorded in the topology (the core's recording points call it). */
  RecordingRing ring(String name, String pseudoname) {
    synchronized (rings) {
      return rings.computeIfAbsent(
          name, n -> new RecordingRing(n, pseudoname, options.capacity(), subscriptions));
    }
  }

  /**
   * Calls {@code listener} with every value recorded from now on, as it is recorded, until the
   * subscription is closed; see {@link RecordingListener} for the threading contract (called on
   * the recording thread, must not block). A merged recording records nothing, so its listeners
   * are never called.
   *
   * @param listener the listener
   * @return the subscription; close it to stop the calls
   */
  public Subscription subscribe(RecordingListener listener) {
    Subscription subscription =
        new Subscription(Objects.requireNonNull(listener, "listener must not be null"));
    subscriptions.add(subscription);
    return subscription;
  }

  /** A {@link RecordingListener}'s subscription to a recording; close it to unsubscribe. */
  public final class Subscription implements AutoCloseable {
    private final RecordingListener listener;
    private final LongAdder failures = new LongAdder();

    private Subscription(RecordingListener listener) {
      this.listener = listener;
    }

    void deliver(RecordedValue<Object> value) {
      try {
        listener.recorded(value);
      } catch (VirtualMachineError e) {
        throw e; // the JVM itself is in trouble
      } catch (Throwable e) { // an Error, a checked exception (Kotlin): never the controller's
        failures.increment();
      }
    }

    /** {@return how many calls of the listener threw (each caught, never reaching the controller)} */
    public long failures() {
      return failures.sum();
    }

    /** Stops the calls; a call under way on another thread may still finish. Idempotent. */
    @Override
    public void close() {
      subscriptions.remove(this);
    }
  }

  /** {@return the options this recording was made with} */
  public RecordingOptions options() {
    return options;
  }

  /** {@return the recorded names, in declaration order (merged: in the order of the recordings)} */
  public Set<String> names() {
    synchronized (rings) {
      return Collections.unmodifiableSet(new LinkedHashSet<>(rings.keySet()));
    }
  }

  /**
   * The pseudoname given to a recorded name.
   *
   * @param name a recorded name
   * @return the pseudoname, or empty if none was given
   * @throws IllegalArgumentException if {@code name} is not recorded
   */
  public Optional<String> pseudoname(String name) {
    return Optional.ofNullable(ring(name).pseudoname());
  }

  /**
   * The latest value recorded under {@code name}; if there is none yet, waits for the first up to
   * {@link RecordingOptions#getTimeout()}.
   *
   * @param name a recorded name
   * @param <T> the value's type, as the caller expects it
   * @return the latest value
   * @throws IllegalArgumentException if {@code name} is not recorded (the message lists those that are)
   * @throws NoSuchElementException if nothing was recorded under it within the timeout
   * @throws InterruptedException if the thread is interrupted while waiting
   */
  public <T> T get(String name) throws InterruptedException {
    return this.<T>getStamped(name, options.getTimeout()).value();
  }

  /**
   * The latest value recorded under {@code name}; if there is none yet, waits for the first up to
   * {@code timeout}.
   *
   * @param name a recorded name
   * @param timeout the longest wait for a first value; zero or positive
   * @param <T> the value's type, as the caller expects it
   * @return the latest value
   * @throws IllegalArgumentException if {@code name} is not recorded
   * @throws NoSuchElementException if nothing was recorded under it within the timeout
   * @throws InterruptedException if the thread is interrupted while waiting
   */
  public <T> T get(String name, Duration timeout) throws InterruptedException {
    return this.<T>getStamped(name, timeout).value();
  }

  /**
   * Like {@link #get(String)}, with the value's time stamps.
   *
   * @param name a recorded name
   * @param <T> the value's type, as the caller expects it
   * @return the latest entry
   * @throws IllegalArgumentException if {@code name} is not recorded
   * @throws NoSuchElementException if nothing was recorded under it within the timeout
   * @throws InterruptedException if the thread is interrupted while waiting
   */
  public <T> RecordedValue<T> getStamped(String name) throws InterruptedException {
    return getStamped(name, options.getTimeout());
  }

  /**
   * Like {@link #get(String, Duration)}, with the value's time stamps.
   *
   * @param name a recorded name
   * @param timeout the longest wait for a first value; zero or positive
   * @param <T> the value's type, as the caller expects it
   * @return the latest entry
   * @throws IllegalArgumentException if {@code name} is not recorded
   * @throws NoSuchElementException if nothing was recorded under it within the timeout
   * @throws InterruptedException if the thread is interrupted while waiting
   */
  public <T> RecordedValue<T> getStamped(String name, Duration timeout)
      throws InterruptedException {
    Objects.requireNonNull(timeout, "timeout must not be null");
    if (timeout.isNegative()) {
      throw new IllegalArgumentException("timeout must be zero or positive, was " + timeout);
    }
    RecordingRing ring = ring(name);
    RecordedValue<Object> latest = ring.awaitLatest(Deadlines.boundedNanos(timeout), finished);
    if (latest == null && finished.getAsBoolean()) {
      throw new NoSuchElementException(
          "nothing was recorded under '" + name + "' in core '" + core + "', and nothing will be:"
              + " the core is closed (or this is a merged recording)");
    }
    if (latest == null) {
      throw new NoSuchElementException(
          "nothing was recorded under '" + name + "' in core '" + core + "' within " + timeout
              + "; use tryGet to check without waiting, or a longer timeout");
    }
    return typed(latest);
  }

  /**
   * The latest value recorded under {@code name}, never waiting.
   *
   * @param name a recorded name
   * @param <T> the value's type, as the caller expects it
   * @return the latest value, or empty if nothing was recorded under it yet
   * @throws IllegalArgumentException if {@code name} is not recorded
   */
  public <T> Optional<T> tryGet(String name) {
    return this.<T>tryGetStamped(name).map(RecordedValue::value);
  }

  /**
   * Like {@link #tryGet(String)}, with the value's time stamps.
   *
   * @param name a recorded name
   * @param <T> the value's type, as the caller expects it
   * @return the latest entry, or empty
   * @throws IllegalArgumentException if {@code name} is not recorded
   */
  public <T> Optional<RecordedValue<T>> tryGetStamped(String name) {
    RecordedValue<Object> latest = ring(name).latest();
    return latest == null ? Optional.empty() : Optional.of(typed(latest));
  }

  /**
   * The values numbered {@code from} (inclusive) to {@code to} (exclusive) under {@code name}
   * that the ring still holds, oldest first. Values that fell out of the ring are missing from
   * the list (see {@link #dropped(String)}).
   *
   * @param name a recorded name
   * @param from the first sequence number, at least 0
   * @param to one past the last, at least {@code from}
   * @param <T> the values' type, as the caller expects it
   * @return a new list, possibly empty
   * @throws IllegalArgumentException if {@code name} is not recorded or the range is invalid
   */
  public <T> List<T> getRange(String name, long from, long to) {
    return values(getRangeStamped(name, from, to));
  }

  /**
   * Like {@link #getRange(String, long, long)}, with the values' time stamps.
   *
   * @param name a recorded name
   * @param from the first sequence number, at least 0
   * @param to one past the last, at least {@code from}
   * @param <T> the values' type, as the caller expects it
   * @return a new list, possibly empty
   * @throws IllegalArgumentException if {@code name} is not recorded or the range is invalid
   */
  public <T> List<RecordedValue<T>> getRangeStamped(String name, long from, long to) {
    if (from < 0 || to < from) {
      throw new IllegalArgumentException(
          "a range of sequence numbers needs 0 <= from <= to, was from " + from + " to " + to);
    }
    return typed(ring(name).entries(e -> e.sequence() >= from && e.sequence() < to));
  }

  /**
   * Every value the ring of {@code name} holds, oldest first.
   *
   * @param name a recorded name
   * @param <T> the values' type, as the caller expects it
   * @return a new list, possibly empty
   * @throws IllegalArgumentException if {@code name} is not recorded
   */
  public <T> List<T> getAll(String name) {
    return values(getAllStamped(name));
  }

  /**
   * Like {@link #getAll(String)}, with the values' time stamps.
   *
   * @param name a recorded name
   * @param <T> the values' type, as the caller expects it
   * @return a new list, possibly empty
   * @throws IllegalArgumentException if {@code name} is not recorded
   */
  public <T> List<RecordedValue<T>> getAllStamped(String name) {
    return typed(ring(name).entries(e -> true));
  }

  /**
   * How many values recorded under {@code name} fell out of its ring.
   *
   * @param name a recorded name
   * @return the count
   * @throws IllegalArgumentException if {@code name} is not recorded
   */
  public long dropped(String name) {
    return ring(name).dropped();
  }

  /**
   * How many values were recorded under {@code name}, those still held and those dropped.
   *
   * @param name a recorded name
   * @return the count
   * @throws IllegalArgumentException if {@code name} is not recorded
   */
  public long recorded(String name) {
    return ring(name).recorded();
  }

  /**
   * Joins recordings, typically of the processes of one Optimus topology, into one that reads
   * like any other but records nothing more: under each name, the entries of every recording that
   * has it, ordered by {@linkplain RecordedValue#wallTime() wall-clock time} (entries with equal
   * times keep the order of the recordings given). Entries keep the sequence numbers of the
   * process that recorded them, so a name recorded in two processes has each number twice. The
   * ring of each name holds all its entries; {@link #dropped(String)} adds up what each recording
   * dropped. The result is a copy: later values recorded in the given recordings are not in it.
   *
   * @param recordings the recordings, at least one
   * @return a new recording
   */
  public static Recording merge(Recording... recordings) {
    return merge(Arrays.asList(recordings));
  }

  /**
   * Joins recordings; see {@link #merge(Recording...)}.
   *
   * @param recordings the recordings, at least one
   * @return a new recording
   */
  public static Recording merge(Collection<Recording> recordings) {
    if (recordings.isEmpty()) {
      throw new IllegalArgumentException("merge needs at least one recording");
    }
    Map<String, List<RecordedValue<Object>>> entries = new LinkedHashMap<>();
    Map<String, Long> dropped = new LinkedHashMap<>();
    Map<String, String> pseudonames = new LinkedHashMap<>();
    List<String> cores = new ArrayList<>();
    int capacity = 1;
    for (Recording recording : recordings) {
      Objects.requireNonNull(recording, "a recording to merge is null");
      cores.add(recording.core);
      capacity = Math.max(capacity, recording.options.capacity());
      for (String name : recording.names()) {
        RecordingRing ring = recording.ring(name);
        entries.computeIfAbsent(name, n -> new ArrayList<>()).addAll(ring.entries(e -> true));
        dropped.merge(name, ring.dropped(), Long::sum);
        if (ring.pseudoname() != null) {
          pseudonames.putIfAbsent(name, ring.pseudoname());
        }
      }
    }
    Map<String, RecordingRing> rings = new LinkedHashMap<>();
    entries.forEach(
        (name, list) -> {
          list.sort(Comparator.comparing(RecordedValue::wallTime));
          rings.put(
              name, RecordingRing.frozen(name, pseudonames.get(name), list, dropped.get(name)));
        });
    RecordingOptions first = recordings.iterator().next().options;
    return new Recording(
        "merged" + cores,
        RecordingOptions.ring(capacity).withGetTimeout(first.getTimeout()),
        rings,
        () -> true);
  }

  private RecordingRing ring(String name) {
    Objects.requireNonNull(name, "name must not be null");
    synchronized (rings) {
      RecordingRing ring = rings.get(name);
      if (ring == null) {
        throw new IllegalArgumentException(
            "nothing is recorded under '" + name + "' in core '" + core + "': the recorded names"
                + " (its sources and chains made of blocks) are " + rings.keySet());
      }
      return ring;
    }
  }

  @SuppressWarnings("unchecked")
  private static <T> RecordedValue<T> typed(RecordedValue<Object> entry) {
    return (RecordedValue<T>) (RecordedValue<?>) entry;
  }

  @SuppressWarnings("unchecked")
  private static <T> List<RecordedValue<T>> typed(List<RecordedValue<Object>> entries) {
    return (List<RecordedValue<T>>) (List<?>) entries;
  }

  private static <T> List<T> values(List<RecordedValue<T>> entries) {
    List<T> out = new ArrayList<>(entries.size());
    for (RecordedValue<T> entry : entries) {
      out.add(entry.value());
    }
    return out;
  }

  @Override
  public String toString() {
    return "Recording[" + core + ", " + names().size() + " names, " + options + "]";
  }
}
