package dev.prime;

import dev.prime.internal.Deadlines;
import dev.prime.internal.RateLimitedLog;
import java.lang.invoke.MethodHandles;
import java.lang.invoke.VarHandle;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Objects;
import java.util.Optional;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.LongAdder;
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
 * not taken, the publisher waits (polling with short timed parks, holding nothing, so the service,
 * close() and other readers go on) up to {@link CoreConfig#publishTimeout()}, then throws {@link
 * QueueFullException} having published nothing. Plain readers ({@link #reader()}, {@link
 * #serviceReader()}, which collectors use) never gate: they are lapped and count what they missed.
 * The publisher keeps the lowest gating cursor it last saw ({@code gate}) and re-reads the gating
 * readers' cursors only when the next slot would lap that cached value, so a publish that is not
 * about to lap a service costs one comparison. The gating readers are an array replaced (copy on
 * write) when one is added or closed; a closed gating reader (its service stopped) stops gating.
 *
 * <p>Publishing: the single-publisher path. {@code claimed} is both the publishers' token and the
 * readers' lap check: it equals {@code count} when nobody publishes and {@code count + 1} while a
 * publisher writes slot {@code count}. A publish takes the token with one compare-and-set of
 * {@code claimed} from {@code count} to {@code count + 1}, writes the slot and then {@code count}
 * (which frees the token). Most sources have one publishing thread (a service's output, an event
 * block fed by one driver or timer), so the compare-and-set never fails: no lock, no queue, no
 * park, and nothing else to detect or declare. A publisher that finds the token taken (several
 * threads publish at once) is the multi-publisher path: it queues on {@code contention}, a lock
 * only contended publishers take, and the first in the queue spins, then yields, then parks
 * briefly until the token is free. Registering or closing a gating reader and closing the source
 * take the token too, so they never race a publish. A publisher waiting for room frees the token
 * while it waits.
 *
 * <p>Reading takes no lock: a reader reads {@code count}, reads the slot and then checks {@code
 * claimed} to see whether a publisher lapped it meanwhile (then it retries, counting what it
 * missed), like an optimistic read of a sequence lock; its cursor moves by compare-and-set, so
 * each value goes to one caller when several threads share a reader. A service's input hands its
 * service every value available in one call ({@link BatchReader}): one read of {@code count} per
 * batch, and per value a slot read and a release store of the cursor; it needs no lap check, since
 * no publisher passes an open gating reader (a closed one stops at the next value). At low rates
 * a batch is one value, taken as soon as it is published.
 *
 * <p>Waiting: a reader with nothing to read first spins watching {@code count} for {@link
 * #SPIN_NANOS} (2 µs), then yields its core between looks until {@link #YIELD_NANOS} (200 µs),
 * because waking a parked thread costs microseconds to milliseconds (on a virtual machine the idle
 * CPU halts and must be woken; on a busy one the woken thread waits for a time slice), far more
 * than a transmission. The budget is measured in time, not in spin rounds: a round's length
 * depends on the CPU's pause instruction and on how the JIT compiled the loop. The spin is short
 * because the reader may share its core with the very thread it waits for: on a machine with two
 * cores the scheduler often keeps a publisher and its service on one core (every sample of the
 * hand-off benchmark's slow forks showed both threads on the same CPU, each with half of it). A
 * reader that spun 50 µs there held the core for 50 µs in which nothing could be published, at
 * every hand-over, twice per burst of values: the hand-off's slow mode (~360 ns a value instead of
 * ~110). Yielding gives the core to the publisher within 2 µs; on a core of its own a yield
 * returns at once and costs a system call, so a reader still sees a value within about a
 * microsecond.
 *
 * <p>Parking without a fence per publish: a reader that spun and yielded in vain announces itself
 * ({@code waiting}, one atomic add per parking wait), registers in {@code sleepers} (raising
 * {@code parked}), looks once more and parks. A publisher writes {@code count} with a release
 * store and reads {@code waiting} with an acquire load, and only if it is not zero does it take
 * a full fence and read {@code parked}, then unpark every sleeper and empty the list: a reader is
 * woken once, not once per value, and a woken reader never contends with the publisher for a
 * lock. The fenced pair ({@code count} then {@code parked} against {@code parked} then {@code
 * count}) means either the publisher sees the sleeper or the sleeper sees the value. A volatile
 * store of {@code count} would fence every publish, and that fence waits for the cache line of
 * {@code count} to come back from the reader's core whenever the reader looked at it since: it
 * made a steady flow 2 to 3 times slower (33–83 ns a value against 20–30 measured without it).
 * The unfenced check can miss only an announcement that was not yet visible when the publisher
 * looked, that is a publish overlapping the announcement, whose value then sits in the
 * publisher's store buffer, which drains in nanoseconds; so the reader's first park after its
 * announcement lasts at most {@link #UNFENCED_WINDOW_NANOS} (50 µs), after which it looks again
 * and parks for as long as it must. The worst case of that race is one value seen 50 µs late; the
 * cost is one extra wake-up per parking wait (a thread that parks for good wakes once more).
 * (On ARM the release store and the acquire load are not reordered at all.) Before the rewrite,
 * readers waited on a condition of the publishers' lock, so a woken reader had to take that lock
 * back while the publisher wanted it for the next value.
 *
 * <p>Layout: {@code claimed} (the token, which a service's input never reads), {@code count}
 * (which every reader watches) and each reader's {@code cursor} are padded onto cache lines of
 * their own ({@link HandOffPadding}): the publisher's compare-and-set of the token stays on a line
 * no reader pulls away, and neither thread's writes evict the fields the other only reads.
 *
 * <p>Copies: with a {@link ValueCodec} (the core's {@code copyValues} option) the ring holds each
 * value encoded at publish time, and every read decodes a copy of its own, as if each reader were
 * another process: a publisher that mutates a value after publishing it, or a reader that mutates
 * what it read, changes nothing for the others; a value the codec refuses fails the publish. A
 * value the codec cannot decode (it broke its contract) is skipped: a service's read that met it
 * throws {@link UndecodableValueException}, naming the service, the source and the codec, which
 * the service reports; a plain reader logs that at WARN and goes on with the next value.
 *
 * @param <T> value type
 */
final class MemorySource<T> extends HandOffPadding.PaddedSequences implements MediaSource<T> {
  /** Rounds between two clock reads of a spinning reader. */
  private static final int SPINS_PER_CLOCK_READ = 16;

  /**
   * How long a reader with nothing to read spins before it starts yielding its core: long enough
   * for the next value of a steady flow from a thread on another core, short enough that a reader
   * sharing its core with the publisher it waits for hands the core over almost at once.
   */
  static final long SPIN_NANOS = TimeUnit.MICROSECONDS.toNanos(2);

  /**
   * How long a reader waits without parking in all (spinning, then yielding, which lets another
   * thread, perhaps the publisher it waits for, run on its core); then it parks until a publish
   * wakes it. Values further apart than this find their reader parked, whatever the spin.
   */
  static final long YIELD_NANOS = TimeUnit.MICROSECONDS.toNanos(200);

  /**
   * How long after a reader announced itself to publishers ({@code waiting}) a publish may still
   * have missed the announcement: the reader's first park after it announced lasts no longer, then
   * it looks again. A publisher that missed the announcement has its value in its CPU's store
   * buffer, which drains in nanoseconds; 50 µs is a margin of thousands.
   */
  static final long UNFENCED_WINDOW_NANOS = TimeUnit.MICROSECONDS.toNanos(50);

  /** {@code announced} of a reader that has not announced itself: see {@code MemoryReader.await}. */
  private static final long NOT_ANNOUNCED = Long.MIN_VALUE;

  /** Longest single park of a publisher waiting for room in a service's input. */
  private static final long MAX_ROOM_PARK_NANOS = TimeUnit.MILLISECONDS.toNanos(1);

  /** Rounds a contended publisher spins for the token, then yields, then parks this long. */
  private static final int TOKEN_SPINS = 128;

  private static final int TOKEN_YIELDS = 64;
  private static final long TOKEN_PARK_NANOS = TimeUnit.MICROSECONDS.toNanos(20);

  private static final VarHandle CLAIMED;
  private static final VarHandle CURSOR;
  private static final VarHandle COUNT;
  private static final VarHandle WAITING;
  private static final VarHandle MISSED;

  static {
    try {
      MethodHandles.Lookup lookup = MethodHandles.lookup();
      CLAIMED = lookup.findVarHandle(HandOffPadding.Claimed.class, "claimed", long.class);
      COUNT = lookup.findVarHandle(HandOffPadding.Sequences.class, "count", long.class);
      WAITING = lookup.findVarHandle(MemorySource.class, "waiting", int.class);
      CURSOR = lookup.findVarHandle(HandOffPadding.Cursor.class, "cursor", long.class);
      MISSED = lookup.findVarHandle(MemorySource.MemoryReader.class, "missed", long.class);
    } catch (ReflectiveOperationException e) {
      throw new ExceptionInInitializerError(e);
    }
  }

  @SuppressWarnings("rawtypes")
  private static final MemorySource.MemoryReader[] NO_GATES = new MemorySource.MemoryReader[0];

  private final PrimeCore core;
  private final String name;
  private final Runnable onReader;
  private final Object[] ring;
  private final int mask; // ring.length - 1 if that is a power of two (the default), else -1
  private final ValueCodec copies; // null: values are shared by reference
  private final long spinNanos; // how long a reader with nothing to read spins
  private final long waitNanos; // how long it spins and yields in all before it parks
  // claimed (the token: count, or count + 1 while a publisher holds it) and count (values fully
  // published, written by the token's holder) are inherited, alone on their cache lines
  private volatile int parked; // sleepers.size(), written under sleepers' monitor
  private volatile int waiting; // readers past their spin, so perhaps parking: changed with WAITING
  private volatile boolean closed; // written by the token's holder
  private volatile MemoryReader[] gates = noGates(); // replaced by the token's holder: inputs
  private long gate = Long.MAX_VALUE; // guarded by the token: lowest gating cursor last seen
  private final ReentrantLock contention = new ReentrantLock(); // publishers finding the token taken
  private final List<Thread> sleepers = new ArrayList<>(); // guarded by itself: parked readers

  private static final Logger LOG = LoggerFactory.getLogger(MemorySource.class);
  private final RateLimitedLog missLog = // one key: this source
      new RateLimitedLog(MemorySource.class.getName());
  private final LongAdder missedByReaders = new LongAdder();

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
    this(core, name, retention, copies, onReader, SPIN_NANOS, YIELD_NANOS);
  }

  /**
   * A source whose readers wait by other budgets than {@link #SPIN_NANOS} and {@link
   * #YIELD_NANOS}: for tests that must reach the sleeper list almost at once (both 0: a reader
   * still looks {@code SPINS_PER_CLOCK_READ} times before it reads the clock, then parks).
   *
   * @param core the owning core
   * @param name the source's name
   * @param retention how many latest values to keep
   * @param copies see {@link #MemorySource(PrimeCore, String, int, ValueCodec, Runnable)}
   * @param onReader see {@link #MemorySource(PrimeCore, String, int, ValueCodec, Runnable)}
   * @param spinNanos how long a reader with nothing to read spins before it yields its core
   * @param waitNanos how long it spins and yields in all before it parks
   */
  MemorySource(
      PrimeCore core,
      String name,
      int retention,
      ValueCodec copies,
      Runnable onReader,
      long spinNanos,
      long waitNanos) {
    if (spinNanos < 0 || waitNanos < spinNanos) {
      throw new IllegalArgumentException(
          "need 0 <= spinNanos <= waitNanos, were " + spinNanos + " and " + waitNanos);
    }
    this.spinNanos = spinNanos;
    this.waitNanos = waitNanos;
    this.copies = copies;
    this.core = Objects.requireNonNull(core, "core");
    this.name = Objects.requireNonNull(name, "name");
    this.onReader = Objects.requireNonNull(onReader, "onReader");
    if (retention < 1) {
      throw new IllegalArgumentException("retention must be at least 1, was " + retention);
    }
    this.ring = newRing(name, retention);
    this.mask = Integer.bitCount(retention) == 1 ? retention - 1 : -1;
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
    if (value == null) { // not requireNonNull with a message supplier: no lambda per publish
      throw new NullPointerException("source '" + name + "' carries no nulls");
    }
    Object stored = copies == null ? value : copies.encode(value);
    long deadline = 0;
    long park = 1_000;
    boolean timed = false;
    while (true) {
      long sequence = claim();
      if (closed) {
        release(sequence);
        throw new CoreClosedException(core.name());
      }
      if (sequence - ring.length >= gate) {
        MemoryReader blocking = lowestGate();
        if (blocking != null && sequence - ring.length >= gate) {
          release(sequence); // wait for room holding nothing
          if (!timed) {
            timed = true;
            deadline = System.nanoTime() + Deadlines.boundedNanos(core.config().publishTimeout());
          }
          park = awaitRoom(blocking, deadline, park);
          continue;
        }
      }
      ring[index(sequence)] = stored;
      COUNT.setRelease(this, sequence + 1); // the value is visible, and the token free
      if ((int) WAITING.getAcquire(this) != 0) {
        wakeSleepers();
      }
      return;
    }
  }

  /**
   * Takes the publishers' token: one compare-and-set when nobody else publishes.
   *
   * @return the sequence number to write, {@code count}; {@code claimed} is now one more
   */
  private long claim() {
    long sequence = count;
    if (claimed == sequence && CLAIMED.compareAndSet(this, sequence, sequence + 1)) {
      return sequence;
    }
    return claimContended();
  }

  /** The multi-publisher path: queue behind other contended publishers, then wait for the token. */
  private long claimContended() {
    contention.lock();
    try {
      for (int round = 0; ; round++) {
        long sequence = count;
        if (claimed == sequence && CLAIMED.compareAndSet(this, sequence, sequence + 1)) {
          return sequence;
        }
        if (round < TOKEN_SPINS) {
          Thread.onSpinWait();
        } else if (round < TOKEN_SPINS + TOKEN_YIELDS) {
          Thread.yield();
        } else {
          LockSupport.parkNanos(this, TOKEN_PARK_NANOS);
        }
      }
    } finally {
      contention.unlock();
    }
  }

  /** Frees the token without publishing: {@code sequence} is what {@link #claim()} returned. */
  private void release(long sequence) {
    claimed = sequence;
  }

  /**
   * Waits (holding nothing) a little for room in the input of {@code blocking}, which was full.
   *
   * @return the next park's length
   * @throws QueueFullException if no room came within the core's publish timeout
   * @throws CoreClosedException if the source closed meanwhile
   */
  private long awaitRoom(MemoryReader blocking, long deadline, long park) {
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
    LockSupport.parkNanos(this, Math.min(park, left));
    if (closed) {
      throw new CoreClosedException(core.name());
    }
    return Math.min(park * 2, MAX_ROOM_PARK_NANOS);
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

  /**
   * A publish's path when some reader announced that it may park: a full fence orders the store of
   * {@code count} before the load of {@code parked} (paired with the sleeper's registration in
   * {@link #sleep}: either this publisher sees the sleeper or the sleeper sees the value).
   */
  private void wakeSleepers() {
    VarHandle.fullFence();
    if (parked != 0) {
      wakeReaders();
    }
  }

  /** Unparks every registered sleeper and empties the list: each is woken once. */
  private void wakeReaders() {
    synchronized (sleepers) {
      for (int i = 0; i < sleepers.size(); i++) {
        LockSupport.unpark(sleepers.get(i));
      }
      sleepers.clear();
      parked = 0;
    }
  }

  /**
   * Parks the calling thread once, registered as a sleeper, unless {@code reader} is ready by
   * then; the caller looks again whatever woke it (a publish, a close, the deadline, an interrupt,
   * the end of the unfenced window or nothing). Within {@link #UNFENCED_WINDOW_NANOS} of the
   * reader's announcement the park is timed to end with the window: a publish that overlapped the
   * announcement may not have looked for sleepers.
   *
   * @param reader the reader waiting
   * @param announced {@link System#nanoTime()} when the reader announced itself to publishers
   * @param deadline {@link System#nanoTime()} to wake at, if {@code timed}
   * @param timed whether to wake at the deadline
   * @throws InterruptedException if the thread is interrupted (its flag is cleared)
   */
  private void sleep(MemoryReader reader, long announced, long deadline, boolean timed)
      throws InterruptedException {
    Thread me = Thread.currentThread();
    synchronized (sleepers) {
      sleepers.add(me);
      parked = sleepers.size(); // volatile: a publisher that writes count later sees this
    }
    try {
      if (Thread.interrupted()) {
        throw new InterruptedException();
      }
      if (!reader.ready()) {
        long now = System.nanoTime();
        long window = announced + UNFENCED_WINDOW_NANOS - now;
        if (window > 0 && (!timed || window < deadline - now)) {
          LockSupport.parkNanos(this, window);
        } else if (timed) {
          LockSupport.parkNanos(this, deadline - now);
        } else {
          LockSupport.park(this);
        }
      }
    } finally {
      synchronized (sleepers) {
        if (sleepers.remove(me)) {
          parked = sleepers.size();
        }
      }
    }
  }

  /** Wakes every waiting reader; later reads throw {@link CoreClosedException}. */
  public void close() {
    long sequence = claim();
    try {
      closed = true;
      gates = noGates();
      gate = Long.MAX_VALUE;
      java.util.Arrays.fill(ring, null);
    } finally {
      release(sequence);
    }
    wakeReaders();
    missLog.flush(); // the misses (and skips) counted since the last line: nobody reads them after the close
  }

  @Override
  public Reader<T> reader() {
    Reader<T> reader = serviceReader();
    onReader.run();
    return reader;
  }

  @Override
  public Reader<T> serviceReader() {
    long sequence = claim(); // no publish moves the oldest value while the reader is placed
    try {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      return new MemoryReader(Math.max(0, sequence - ring.length), null);
    } finally {
      release(sequence);
    }
  }

  /**
   * The input of the in-process service {@code service}: a reader, positioned like {@link
   * #reader()} and not recorded in the topology, that gates publishers (a publish never overwrites
   * a value it has not read). Close it when the service stops, so that it stops gating. Its
   * service is its only consumer, which takes values in batches ({@link BatchReader}).
   *
   * @param service the service's name, for {@link QueueFullException}
   * @return a new gating reader
   */
  Reader<T> serviceInput(String service) {
    Objects.requireNonNull(service, "service");
    long sequence = claim();
    try {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      MemoryReader reader = new MemoryReader(Math.max(0, sequence - ring.length), service);
      MemoryReader[] more = java.util.Arrays.copyOf(gates, gates.length + 1);
      more[gates.length] = reader;
      gates = more;
      gate = Math.min(gate, reader.cursor);
      return reader;
    } finally {
      release(sequence);
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

  /**
   * {@return how many takes announced that they may park and have not ended: publishers take the
   * fenced path while it is not zero, so every take must withdraw its announcement; for tests}
   */
  int announcedReaders() {
    return waiting;
  }

  /** {@return how many values this source's readers missed in all, for metrics} */
  long missedByReaders() {
    return missedByReaders.sum();
  }

  /** Stops {@code reader} gating publishers. */
  private void ungate(MemoryReader reader) {
    long sequence = claim();
    try {
      MemoryReader[] current = gates;
      for (int i = 0; i < current.length; i++) {
        if (current[i] == reader) {
          MemoryReader[] fewer = java.util.Arrays.copyOf(current, current.length - 1);
          System.arraycopy(current, i + 1, fewer, i, current.length - 1 - i);
          gates = fewer;
          break;
        }
      }
      gate = Long.MIN_VALUE; // re-read at the next publish that could lap
    } finally {
      release(sequence);
    }
  }

  /**
   * The slot of {@code sequence}: a mask when the ring's length is a power of two (the default
   * retention, 1024), so a publish costs no 64-bit division (tens of cycles on x86); else the
   * remainder.
   */
  private int index(long sequence) {
    return mask >= 0 ? (int) sequence & mask : (int) (sequence % ring.length);
  }

  @SuppressWarnings("unchecked")
  private T decode(Object stored, String service) {
    if (copies == null) {
      return (T) stored;
    }
    try {
      return (T) copies.decode((byte[]) stored);
    } catch (VirtualMachineError e) {
      throw e;
    } catch (RuntimeException | Error e) {
      throw new UndecodableValueException(
          service == null ? "a reader" : "service '" + service + "'",
          name,
          copies,
          (byte[]) stored,
          e);
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

  private final class MemoryReader extends HandOffPadding.PaddedCursor
      implements Reader<T>, BatchReader<T> {
    // cursor (inherited, alone on its cache lines): moved by compare-and-set, or by the release
    // stores of its only consumer (a service input's batches)
    private volatile long missed; // added to with MISSED
    private volatile boolean readerClosed;
    private final String service; // null: a plain reader, which never gates

    MemoryReader(long cursor, String service) {
      super(cursor);
      this.service = service;
    }

    /** The next value if one is published, else null; never blocks. */
    private T next() {
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
          if (CURSOR.compareAndSet(this, position, oldest)) {
            recordMissed(oldest - position);
          }
          continue;
        }
        Object value = ring[index(position)];
        VarHandle.acquireFence(); // read the slot before checking that nobody overwrote it
        if (claimed - ring.length > position || value == null) {
          Thread.onSpinWait(); // lapped while reading (or closing): look again
          continue;
        }
        if (CURSOR.compareAndSet(this, position, position + 1)) {
          if (service != null) {
            return decode(value, service); // a service reports a value it cannot decode
          }
          try {
            return decode(value, null);
          } catch (UndecodableValueException e) {
            skipped(e); // as a distributed media's reader skips it
          }
        }
      }
    }

    /**
     * Logs a value this plain reader skipped because the codec could not decode it: the first of a
     * burst in full, then counted, at most one line per {@value RateLimitedLog#DEFAULT_SECONDS} s.
     */
    private void skipped(UndecodableValueException e) {
      missLog.record(
          "a reader of source '" + name + "' of core '" + core.name() + "' skipped values",
          1,
          "codec " + copies + ": " + e.getCause(),
          () ->
              LOG.warn(
                  "{} (further ones are counted, at most one line per {} s)",
                  e.getMessage(),
                  RateLimitedLog.DEFAULT_SECONDS));
    }

    private void recordMissed(long lost) {
      MISSED.getAndAdd(this, lost);
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

    /**
     * Waits once for something to read: spins, then yields the core between looks, then announces
     * the reader to publishers and parks; the caller looks again after each call. {@code
     * announced} carries the announcement from call to call of one take, so a take announces once
     * however often it parks, and the take withdraws it ({@link #withdraw}) when it ends.
     *
     * <p>Spinning for {@code spinNanos} ({@link #SPIN_NANOS}) is for steady flows, where the next
     * value comes within a microsecond; yielding, until {@code waitNanos} ({@link #YIELD_NANOS})
     * in all, for a publisher that shares the reader's core. Neither is announced: publishers look
     * for sleepers only when some reader announced that it may park, so a flow whose reader never
     * parks costs its publishers no fence. The first park after the announcement ends with {@link
     * #UNFENCED_WINDOW_NANOS} (see {@link MemorySource#sleep}). Budgets are time, not rounds, so
     * they do not depend on how a JVM compiled the loop or on the CPU's pause instruction.
     *
     * @param announced when this take announced itself, or {@link #NOT_ANNOUNCED}
     * @param deadline {@link System#nanoTime()} to give up at, if {@code timed}
     * @param timed whether there is a deadline
     * @return when this take announced itself, or {@link #NOT_ANNOUNCED}
     * @throws InterruptedException if the thread is interrupted while parked
     */
    private long await(long announced, long deadline, boolean timed) throws InterruptedException {
      boolean announcing = announced == NOT_ANNOUNCED;
      if (announcing) {
        if (spin(deadline, timed) || yieldCore(System.nanoTime(), deadline, timed)) {
          return NOT_ANNOUNCED;
        }
        WAITING.getAndAdd(MemorySource.this, 1);
        long now = System.nanoTime();
        announced = now == NOT_ANNOUNCED ? now + 1 : now;
      }
      try {
        if (!timed || deadline - System.nanoTime() > 0) {
          sleep(this, announced, deadline, timed);
        }
      } catch (InterruptedException | RuntimeException | Error e) {
        if (announcing) { // the caller never learns of this announcement: withdraw it here
          withdraw(announced);
        }
        throw e;
      }
      return announced;
    }

    /** Ends the announcement {@link #await} made, if it made one. */
    private void withdraw(long announced) {
      if (announced != NOT_ANNOUNCED) {
        WAITING.getAndAdd(MemorySource.this, -1);
      }
    }

    /** Spins for {@code spinNanos} (or to the deadline); whether the reader is ready. */
    private boolean spin(long deadline, boolean timed) {
      for (int i = 0; i < SPINS_PER_CLOCK_READ; i++) { // most waits of a steady flow end here
        if (ready()) {
          return true;
        }
        Thread.onSpinWait();
      }
      long start = System.nanoTime();
      long now = start;
      while (now - start < spinNanos && !(timed && now - deadline >= 0)) {
        for (int i = 0; i < SPINS_PER_CLOCK_READ; i++) {
          if (ready()) {
            return true;
          }
          Thread.onSpinWait();
        }
        now = System.nanoTime();
      }
      return ready();
    }

    /**
     * Yields the core between looks from {@code announced} until {@code waitNanos - spinNanos}
     * have passed (or the deadline); whether the reader is ready.
     */
    private boolean yieldCore(long announced, long deadline, boolean timed) {
      long now = announced;
      while (now - announced < waitNanos - spinNanos && !(timed && now - deadline >= 0)) {
        Thread.yield();
        if (ready()) {
          return true;
        }
        now = System.nanoTime();
      }
      return ready();
    }

    @Override
    public T take() throws InterruptedException {
      long announced = NOT_ANNOUNCED;
      try {
        while (true) {
          T value = next();
          if (value != null) {
            return value;
          }
          announced = await(announced, 0, false);
        }
      } finally {
        withdraw(announced);
      }
    }

    @Override
    public Optional<T> take(Duration timeout) throws InterruptedException {
      Objects.requireNonNull(timeout, "timeout must not be null");
      long nanos = timeout.isNegative() ? 0 : Deadlines.boundedNanos(timeout);
      long deadline = System.nanoTime() + nanos;
      long announced = NOT_ANNOUNCED;
      try {
        while (true) {
          T value = next();
          if (value != null) {
            return Optional.of(value);
          }
          if (deadline - System.nanoTime() <= 0) {
            return Optional.empty();
          }
          announced = await(announced, deadline, true);
        }
      } finally {
        withdraw(announced);
      }
    }

    /**
     * {@inheritDoc}
     *
     * <p>For the reader's only consumer (a service's input): values are handed out by release
     * stores of the cursor, not by compare-and-set. A plain reader hands out one value, by {@link
     * #take()}.
     */
    @Override
    public void takeAvailable(BatchReader.Sink<? super T> sink) throws InterruptedException {
      if (service == null) {
        sink.accept(take());
        return;
      }
      long announced = NOT_ANNOUNCED;
      try {
        while (true) {
          long available = count;
          ensureReaderOpen();
          if (closed) {
            throw new CoreClosedException(core.name());
          }
          long position = cursor;
          if (position >= available) {
            announced = await(announced, 0, false);
            continue;
          }
          if (announced != NOT_ANNOUNCED) { // values came: a publisher need not look for us
            withdraw(announced);
            announced = NOT_ANNOUNCED;
          }
          Object[] slots = ring;
          int index = index(position);
          while (true) {
            Object value = slots[index];
            VarHandle.acquireFence(); // read the slot before checking that this input still gates
            if (readerClosed || value == null) {
              break; // closed meanwhile: the checks above throw
            }
            CURSOR.setRelease(this, ++position); // the slot is read: a publisher may reuse it
            if (!sink.accept(decode(value, service))) {
              return;
            }
            if (position == available) {
              return;
            }
            if (++index == slots.length) {
              index = 0;
            }
          }
        }
      } finally {
        withdraw(announced);
      }
    }

    @Override
    public Optional<T> poll() {
      return Optional.ofNullable(next());
    }

    @Override
    public List<T> drain() {
      List<T> values = new ArrayList<>();
      T value;
      while ((value = next()) != null) {
        values.add(value);
      }
      return values;
    }

    @Override
    public long missed() {
      ensureReaderOpen();
      if (closed) {
        throw new CoreClosedException(core.name());
      }
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
      wakeReaders();
    }

    @Override
    public String toString() {
      return "Reader[" + name + "]";
    }
  }

  /**
   * The ring of {@code retention} slots, allocated up front: a retention this JVM cannot allocate
   * (the configuration accepts up to {@code Integer.MAX_VALUE}, which a media that keeps sources
   * outside the process may hold) is refused with a message that says what to change, not with an {@link
   * OutOfMemoryError} that a declaration would pass on.
   */
  private static Object[] newRing(String name, int retention) {
    try {
      return new Object[retention];
    } catch (OutOfMemoryError tooLarge) {
      throw new IllegalArgumentException(
          "source '"
              + name
              + "' cannot retain "
              + retention
              + " values: the in-memory media keep a source's retention in a ring of that many"
              + " slots allocated when the source is declared, and this JVM could not allocate it ("
              + tooLarge.getMessage()
              + "); lower CoreConfig.Builder.sourceRetention or give the JVM more heap (-Xmx)",
          tooLarge);
    }
  }

}
