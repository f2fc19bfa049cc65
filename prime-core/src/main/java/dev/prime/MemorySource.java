package dev.prime;

import dev.prime.internal.RateLimitedLog;
import java.lang.invoke.VarHandle;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Objects;
import java.util.Optional;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.locks.Condition;
import java.util.concurrent.locks.LockSupport;
import java.util.concurrent.locks.ReentrantLock;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * An in-memory, broadcast source: the default source of every media that runs in one process.
 * Package-private next to {@link PrimeCore}, whose default it is: the API package never depends on
 * {@code dev.prime.internal}, which depends on nothing else of Prime (see PackageCyclesTest).
 *
 * <p>Design: values go into a ring buffer of {@code retention} slots, indexed by a global
 * sequence number. A reader is just a cursor (the sequence number of its next value), so any
 * number of readers cost no memory per value, late readers start at the oldest retained value,
 * and a plain reader that falls more than {@code retention} behind skips to the oldest retained
 * value and counts what it missed. Memory is bounded by the retention whatever the readers do.
 *
 * <p>Service inputs are queues: a reader made by {@link #serviceInput(String)} (the input of an
 * in-process service) gates the publishers, like a gating sequence of a Disruptor. A publish never
 * overwrites a slot such a reader has not read yet: when the ring is full of values a service has
 * not taken, the publisher waits (polling with short timed parks, the lock released, so the
 * service, close() and other readers go on) up to {@link CoreConfig#publishTimeout()}, then throws
 * {@link QueueFullException} having published nothing. Plain readers ({@link #reader()}, {@link
 * #serviceReader()}, which collectors use) never gate: they are lapped and count what they missed.
 * Hot path: the publisher keeps the lowest gating cursor it last saw ({@code gate}, under the
 * lock) and re-reads the gating readers' cursors only when the next slot would lap that cached
 * value, so a publish that is not about to lap a service costs one comparison and allocates
 * nothing. The gating readers are an array replaced (copy on write) under the lock when one is
 * added or closed; a closed gating reader (its service stopped) stops gating. Closing the source
 * wakes waiting publishers, which then fail with {@link CoreClosedException}.
 *
 * <p>Threading: publishers serialise on one lock. Readers take no shared lock: a publisher
 * announces the sequence number it is about to write ({@code claimed}), writes the slot, then
 * publishes the new {@code count}; a reader reads {@code count}, reads the slot and then checks
 * {@code claimed} to see whether a publisher lapped it meanwhile (then it retries, counting what
 * it missed), like an optimistic read of a sequence lock. A reader with nothing to read first
 * spins briefly (at most {@link #SPINS} rounds of {@link Thread#onSpinWait()}, tens of
 * microseconds) watching {@code count}, because waking a parked thread costs microseconds, far
 * more than a transmission; only then it parks on the lock's condition, which a publisher
 * signals only when someone waits.
 *
 * <p>Copies: with a {@link ValueCodec} (the core's {@code copyValues} option) the ring holds each
 * value encoded at publish time, and every read decodes a copy of its own, as if each reader were
 * another process: a publisher that mutates a value after publishing it, or a reader that mutates
 * what it read, changes nothing for the others; a value the codec refuses fails the publish.
 *
 * @param <T> value type
 */
final class MemorySource<T> implements MediaSource<T> {
  /** Rounds a reader spins, watching for a publication, before it parks. */
  static final int SPINS = 4_096;

  /** Longest single park of a publisher waiting for room in a service's input. */
  private static final long MAX_ROOM_PARK_NANOS = TimeUnit.MILLISECONDS.toNanos(1);

  @SuppressWarnings("rawtypes")
  private static final MemorySource.MemoryReader[] NO_GATES = new MemorySource.MemoryReader[0];

  private final PrimeCore core;
  private final String name;
  private final Runnable onReader;
  private final Object[] ring;
  private final ValueCodec copies; // null: values are shared by reference
  private final ReentrantLock lock = new ReentrantLock();
  private final Condition published = lock.newCondition();
  private volatile long claimed; // written under lock: sequence numbers handed to publishers
  private volatile long count; // written under lock: values fully published
  private volatile boolean closed; // written under lock
  private int waiting; // guarded by lock: readers parked until the next publication
  private MemoryReader[] gates = noGates(); // guarded by lock, replaced on change: service inputs
  private long gate = Long.MAX_VALUE; // guarded by lock: lowest gating cursor last seen

  private static final Logger LOG = LoggerFactory.getLogger(MemorySource.class);
  private final RateLimitedLog missLog = new RateLimitedLog(MemorySource.class.getName()); // one key: this source
  private final java.util.concurrent.atomic.LongAdder missedByReaders = new java.util.concurrent.atomic.LongAdder();

  /**
   * @param core the owning core
   * @param name the source's name
   * @param retention how many latest values to keep
   */
  MemorySource(PrimeCore core, String name, int retention) {
    this(core, name, retention, null, () -> {});
  }

  /**
   * @param core the owning core
   * @param name the source's name
   * @param retention how many latest values to keep
   * @param copies encodes each value at publish and decodes it for each read; {@code null} to
   *     share values by reference
   * @param onReader called when the program opens a reader ({@link #reader()}, not {@link
   *     #serviceReader()}), before it is made: the core records it in its topology
   */
  MemorySource(
      PrimeCore core, String name, int retention, ValueCodec copies, Runnable onReader) {
    this.copies = copies;
    this.core = Objects.requireNonNull(core, "core");
    this.name = Objects.requireNonNull(name, "name");
    this.onReader = Objects.requireNonNull(onReader, "onReader");
    if (retention < 1) {
      throw new IllegalArgumentException("retention must be at least 1, was " + retention);
    }
    this.ring = new Object[retention];
  }

  @Override
  public PrimeCore core() {
    return core;
  }

  @Override
  public String name() {
    return name;
  }

  /**
   * Publishes a value to every reader.
   *
   * @param value not null
   * @throws CoreClosedException if the core is closed
   */
  public void publish(T value) {
    Objects.requireNonNull(value, () -> "source '" + name + "' carries no nulls");
    Object stored = copies == null ? value : copies.encode(value);
    lock.lock();
    try {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      long sequence = count;
      if (sequence - ring.length >= gate) {
        awaitRoom();
        sequence = count; // another publisher may have gone first while this one waited
      }
      claimed = sequence + 1;
      VarHandle.storeStoreFence(); // the claim is visible before the slot changes
      ring[(int) (sequence % ring.length)] = stored;
      count = sequence + 1;
      if (waiting > 0) {
        published.signalAll();
      }
    } finally {
      lock.unlock();
    }
  }

  /**
   * Waits, the lock held on entry and exit but released while parked, until publishing the next
   * value overwrites no value a gating reader has not read.
   *
   * @throws QueueFullException if no room came within the core's publish timeout
   * @throws CoreClosedException if the source closed meanwhile
   */
  private void awaitRoom() {
    long deadline = 0;
    long park = 1_000;
    boolean timed = false;
    while (true) {
      MemoryReader blocking = lowestGate();
      if (blocking == null || count - ring.length < gate) {
        return;
      }
      if (!timed) {
        timed = true;
        deadline = System.nanoTime() + saturatedNanos(core.config().publishTimeout());
      }
      long left = deadline - System.nanoTime();
      if (Thread.currentThread().isInterrupted()) {
        throw new PrimeException(
            "publish to source '"
                + name
                + "' was interrupted while it waited for room in a service's input; nothing was"
                + " published (the thread's interrupt flag is kept)");
      }
      if (left <= 0) {
        throw queueFull(blocking);
      }
      lock.unlock();
      try {
        LockSupport.parkNanos(this, Math.min(park, left));
      } finally {
        lock.lock();
      }
      park = Math.min(park * 2, MAX_ROOM_PARK_NANOS);
      if (closed) {
        throw new CoreClosedException(core.name());
      }
    }
  }

  /** Re-reads the gating cursors into {@code gate}; the gating reader furthest behind, or null. */
  private MemoryReader lowestGate() {
    MemoryReader lowest = null;
    long min = Long.MAX_VALUE;
    for (MemoryReader reader : gates) {
      long cursor = reader.cursor;
      if (!reader.readerClosed && cursor < min) {
        min = cursor;
        lowest = reader;
      }
    }
    gate = min;
    return lowest;
  }

  private QueueFullException queueFull(MemoryReader blocking) {
    Duration timeout = core.config().publishTimeout();
    return new QueueFullException(
        blocking.service,
        ring.length,
        "publish to source '"
            + name
            + "' refused, nothing was published: the input of service '"
            + blocking.service
            + "' holds "
            + ring.length
            + " values it has not processed (its capacity, the source retention) and no room came"
            + " within "
            + timeout
            + (Thread.currentThread().isInterrupted() ? " (the publisher was interrupted)" : "")
            + ". Is '"
            + blocking.service
            + "' stuck or slow, or publishing into its own input? Make it faster, publish fewer"
            + " values, give it more room with CoreConfig.Builder.sourceRetention(n), or wait"
            + " longer with CoreConfig.Builder.publishTimeout(d).");
  }

  /** Wakes every waiting reader; later reads throw {@link CoreClosedException}. */
  public void close() {
    lock.lock();
    try {
      closed = true;
      gates = noGates();
      gate = Long.MAX_VALUE;
      java.util.Arrays.fill(ring, null);
      published.signalAll();
    } finally {
      lock.unlock();
    }
  }

  @Override
  public Reader<T> reader() {
    Reader<T> reader = serviceReader();
    onReader.run();
    return reader;
  }

  @Override
  public Reader<T> serviceReader() {
    lock.lock();
    try {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      return new MemoryReader(Math.max(0, count - ring.length));
    } finally {
      lock.unlock();
    }
  }

  /**
   * The input of the in-process service {@code service}: a reader, positioned like {@link
   * #reader()} and not recorded in the topology, that gates publishers (a publish never overwrites
   * a value it has not read). Close it when the service stops, so that it stops gating.
   *
   * @param service the service's name, for {@link QueueFullException}
   * @return a new gating reader
   */
  Reader<T> serviceInput(String service) {
    Objects.requireNonNull(service, "service");
    lock.lock();
    try {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      MemoryReader reader = new MemoryReader(Math.max(0, count - ring.length), service);
      MemoryReader[] more = java.util.Arrays.copyOf(gates, gates.length + 1);
      more[gates.length] = reader;
      gates = more;
      gate = Math.min(gate, reader.cursor);
      return reader;
    } finally {
      lock.unlock();
    }
  }

  /**
   * {@return how many values published to this source {@code input} (a reader of this source) has
   * not taken yet: the depth of a service's input queue, for metrics; 0 for another reader}
   */
  long backlog(Reader<?> input) {
    return input instanceof MemorySource<?>.MemoryReader reader
        ? Math.max(0, count - reader.cursor)
        : 0;
  }

  /** {@return how many values this source's readers missed in all, for metrics} */
  long missedByReaders() {
    return missedByReaders.sum();
  }

  /** Stops {@code reader} gating publishers. */
  private void ungate(MemoryReader reader) {
    lock.lock();
    try {
      for (int i = 0; i < gates.length; i++) {
        if (gates[i] == reader) {
          MemoryReader[] fewer = java.util.Arrays.copyOf(gates, gates.length - 1);
          System.arraycopy(gates, i + 1, fewer, i, gates.length - 1 - i);
          gates = fewer;
          break;
        }
      }
      gate = Long.MIN_VALUE; // re-read at the next publish that could lap
    } finally {
      lock.unlock();
    }
  }

  @SuppressWarnings("unchecked")
  private MemoryReader[] noGates() {
    return (MemoryReader[]) NO_GATES;
  }

  @Override
  public String toString() {
    return "MemorySource[" + name + "]";
  }

  private final class MemoryReader implements Reader<T> {
    private volatile long cursor; // written under this reader's monitor; read anywhere as a hint
    private long missed; // guarded by this reader's monitor
    private volatile boolean readerClosed;
    private final String service; // null: a plain reader, which never gates

    MemoryReader(long cursor) {
      this(cursor, null);
    }

    MemoryReader(long cursor, String service) {
      this.cursor = cursor;
      this.service = service;
    }

    /** The next value if one is published, else null; never blocks on publishers. */
    @SuppressWarnings("unchecked")
    private synchronized T next() {
      while (true) {
        long available = count;
        ensureReaderOpen();
        if (closed) {
          throw new CoreClosedException(core.name());
        }
        long position = cursor;
        if (position >= available) {
          return null;
        }
        long oldest = available - ring.length;
        if (position < oldest) {
          long lost = oldest - position;
          missed += lost;
          missedByReaders.add(lost);
          missLog.record(
              "a reader of source '" + name + "' of core '" + core.name() + "' missed values",
              lost,
              lost + " values",
              () ->
                  LOG.warn(
                      "a reader of source '{}' of core '{}' missed {} values: it fell more than"
                          + " the retention ({}) behind; read faster or raise"
                          + " CoreConfig.sourceRetention (further misses are counted, at most one"
                          + " line per {} s)",
                      name,
                      core.name(),
                      lost,
                      ring.length,
                      RateLimitedLog.DEFAULT_SECONDS));
          position = oldest;
        }
        Object value = ring[(int) (position % ring.length)];
        VarHandle.acquireFence(); // read the slot before checking that nobody overwrote it
        if (claimed - ring.length > position || value == null) {
          cursor = position; // lapped while reading (or closing): look again
          Thread.onSpinWait();
          continue;
        }
        cursor = position + 1;
        return (T) (copies == null ? value : copies.decode((byte[]) value));
      }
    }

    /** Whether {@link #next()} would return a value or throw. */
    private boolean ready() {
      return closed || readerClosed || count != cursor;
    }

    private void ensureReaderOpen() {
      if (readerClosed) {
        throw new IllegalStateException(
            "reader closed: this reader of source '"
                + name
                + "' was closed by Reader.close(); take a new reader from the source");
      }
    }

    /** Spins while there is nothing to read, for at most {@link #SPINS} rounds. */
    private void spin() {
      for (int i = 0; i < SPINS && !ready(); i++) {
        Thread.onSpinWait();
      }
    }

    @Override
    public T take() throws InterruptedException {
      while (true) {
        spin();
        T value = next();
        if (value != null) {
          return value;
        }
        lock.lockInterruptibly();
        try {
          while (!ready()) {
            waiting++;
            try {
              published.await();
            } finally {
              waiting--;
            }
          }
        } finally {
          lock.unlock();
        }
      }
    }

    @Override
    public Optional<T> take(Duration timeout) throws InterruptedException {
      Objects.requireNonNull(timeout, "timeout must not be null");
      long nanos = timeout.isNegative() ? 0 : saturatedNanos(timeout);
      long deadline = System.nanoTime() + nanos;
      while (true) {
        T value = next();
        if (value != null) {
          return Optional.of(value);
        }
        long remaining = deadline - System.nanoTime();
        if (remaining <= 0) {
          return Optional.empty();
        }
        lock.lockInterruptibly();
        try {
          while (!ready() && remaining > 0) {
            waiting++;
            try {
              remaining = published.awaitNanos(remaining);
            } finally {
              waiting--;
            }
          }
        } finally {
          lock.unlock();
        }
      }
    }

    @Override
    public Optional<T> poll() {
      return Optional.ofNullable(next());
    }

    @Override
    public synchronized List<T> drain() {
      List<T> values = new ArrayList<>();
      T value;
      while ((value = next()) != null) {
        values.add(value);
      }
      return values;
    }

    @Override
    public synchronized long missed() {
      ensureReaderOpen();
      return missed;
    }

    /**
     * A reader is only a cursor, so closing it releases nothing but itself: later calls fail, and
     * readers waiting in {@code take} wake up to fail.
     */
    @Override
    public void close() {
      if (readerClosed) {
        return;
      }
      readerClosed = true;
      if (service != null) {
        ungate(this);
      }
      lock.lock();
      try {
        published.signalAll();
      } finally {
        lock.unlock();
      }
    }

    @Override
    public String toString() {
      return "Reader[" + name + "]";
    }
  }

  private static long saturatedNanos(Duration d) {
    try {
      return d.toNanos();
    } catch (ArithmeticException e) {
      return TimeUnit.DAYS.toNanos(365);
    }
  }
}
