package dev.prime;

import dev.prime.spi.MediaSource;
import dev.prime.spi.ValueCodec;
import java.lang.invoke.VarHandle;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Objects;
import java.util.Optional;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.locks.Condition;
import java.util.concurrent.locks.ReentrantLock;

/**
 * An in-memory, broadcast source: the default source of every media that runs in one process.
 * Package-private next to {@link PrimeCore}, whose default it is: the API package never depends on
 * {@code dev.prime.internal}, which depends on nothing else of Prime (see PackageCyclesTest).
 *
 * <p>Design: values go into a ring buffer of {@code retention} slots, indexed by a global
 * sequence number. A reader is just a cursor (the sequence number of its next value), so any
 * number of readers cost no memory per value, late readers start at the oldest retained value,
 * and a reader that falls more than {@code retention} behind skips to the oldest retained value
 * and counts what it missed. Memory is bounded by the retention whatever the readers do.
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

  /** Wakes every waiting reader; later reads throw {@link CoreClosedException}. */
  public void close() {
    lock.lock();
    try {
      closed = true;
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

  @Override
  public String toString() {
    return "MemorySource[" + name + "]";
  }

  private final class MemoryReader implements Reader<T> {
    private volatile long cursor; // written under this reader's monitor; read anywhere as a hint
    private long missed; // guarded by this reader's monitor
    private volatile boolean readerClosed;

    MemoryReader(long cursor) {
      this.cursor = cursor;
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
          missed += oldest - position;
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
