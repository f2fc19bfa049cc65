package dev.prime.internal;

import dev.prime.CoreClosedException;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
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
 *
 * <p>Design: values go into a ring buffer of {@code retention} slots, indexed by a global
 * sequence number. A reader is just a cursor (the sequence number of its next value), so any
 * number of readers cost no memory per value, late readers start at the oldest retained value,
 * and a reader that falls more than {@code retention} behind skips to the oldest retained value
 * and counts what it missed. One lock guards the ring and every cursor; publishing signals the
 * readers blocked in {@code take}. Memory is bounded by the retention whatever the readers do.
 *
 * @param <T> value type
 */
public final class MemorySource<T> implements Source<T> {
  private final PrimeCore core;
  private final String name;
  private final Object[] ring;
  private final ReentrantLock lock = new ReentrantLock();
  private final Condition published = lock.newCondition();
  private long count; // guarded by lock: values published so far
  private boolean closed; // guarded by lock

  /**
   * @param core the owning core
   * @param name the source's name
   * @param retention how many latest values to keep
   */
  public MemorySource(PrimeCore core, String name, int retention) {
    this.core = Objects.requireNonNull(core, "core");
    this.name = Objects.requireNonNull(name, "name");
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
    lock.lock();
    try {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      ring[(int) (count % ring.length)] = value;
      count++;
      published.signalAll();
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
    private long cursor; // guarded by lock
    private long missed; // guarded by lock

    MemoryReader(long cursor) {
      this.cursor = cursor;
    }

    /** Next value if any; caller holds the lock. */
    @SuppressWarnings("unchecked")
    private T next() {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      if (cursor == count) {
        return null;
      }
      long oldest = count - ring.length;
      if (cursor < oldest) {
        missed += oldest - cursor;
        cursor = oldest;
      }
      T value = (T) ring[(int) (cursor % ring.length)];
      cursor++;
      return value;
    }

    @Override
    public T take() throws InterruptedException {
      lock.lockInterruptibly();
      try {
        T value;
        while ((value = next()) == null) {
          published.await();
        }
        return value;
      } finally {
        lock.unlock();
      }
    }

    @Override
    public Optional<T> take(Duration timeout) throws InterruptedException {
      Objects.requireNonNull(timeout, "timeout must not be null");
      long nanos = timeout.isNegative() ? 0 : saturatedNanos(timeout);
      lock.lockInterruptibly();
      try {
        T value;
        while ((value = next()) == null) {
          if (nanos <= 0) {
            return Optional.empty();
          }
          nanos = published.awaitNanos(nanos);
        }
        return Optional.of(value);
      } finally {
        lock.unlock();
      }
    }

    @Override
    public Optional<T> poll() {
      lock.lock();
      try {
        return Optional.ofNullable(next());
      } finally {
        lock.unlock();
      }
    }

    @Override
    public List<T> drain() {
      lock.lock();
      try {
        List<T> values = new ArrayList<>();
        T value;
        while ((value = next()) != null) {
          values.add(value);
        }
        return values;
      } finally {
        lock.unlock();
      }
    }

    @Override
    public long missed() {
      lock.lock();
      try {
        return missed;
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
