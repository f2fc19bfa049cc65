package dev.prime;

import java.util.HashSet;
import java.util.Objects;
import java.util.Set;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;
import java.util.function.BooleanSupplier;

/**
 * Lets several callers share one block without ever running it concurrently: calls run one at a
 * time, in the order they came (first come, first served), so no caller starves.
 *
 * <p>A call from inside the block (the block calls its own isolated chain, on the thread that
 * runs it) would wait for itself: it fails at once with an {@link IllegalStateException} instead.
 *
 * <p>A caller waiting for its turn honours interruption: it stops waiting, keeps its interrupt
 * flag set and gets a {@link PrimeException}; the block is not run for it, and the callers behind
 * it keep their order. A waiting caller also runs a check given by the owner every {@value
 * #CHECK_MILLIS} ms (a core passes its open check, so closing the core ends the wait with {@link
 * dev.prime.CoreClosedException}). Where the block runs on a service's thread for a caller
 * elsewhere (Optimus), the owner also says whether that caller gave up ({@link
 * PrimeCore#callerGaveUp}): asked every {@value #CHECK_MILLIS} ms of the wait and once when the
 * turn comes after a wait (never when the block was free), a yes ends the wait with a {@link
 * PrimeException}, and the block is not run for that call either.
 *
 * <p>Design note: a ticket queue. A caller takes the next ticket (one atomic increment) and
 * runs at once if its ticket is the one being served ({@link #serving}); finishing serves the
 * next ticket with one volatile write. Only then, if a caller waits or gave up, does it enter the
 * monitor {@link #turns} to skip the tickets of callers that gave up ({@link #abandoned}) and to
 * wake the waiters: so a call that found the block free costs an atomic increment and two
 * volatile writes, and no call into the VM. A caller that must wait first spins for {@link
 * #SPIN_NANOS}, looking at {@code serving}: a short block's turn passes to it without the monitor
 * or a wake-up (a parked thread takes microseconds to wake). Then it waits on the monitor, in
 * slices of {@value #CHECK_MILLIS} ms for the checks, and keeps its place while it checks (a lock
 * taken with timed attempts would not: a timed-out attempt rejoins the queue at its tail). A
 * spinning caller only reads {@code serving}, so it changes none of the races below. Races: a
 * finisher writes {@code serving}, then reads {@link #waiting} and {@link #abandonedCount}; a
 * waiter or a caller giving up writes those, then reads {@code serving} (all volatile), so at least
 * one of the two sees the other: no wake-up and no turn is lost. {@code serving} is written only by
 * the caller whose turn it is, or, under the monitor, by whoever skips an abandoned ticket (whose
 * turn nobody owns). The checks run outside the monitor, at most once per slice. Memory: three
 * counters and the set of abandoned tickets still queued.
 *
 * @param <I> input type
 * @param <O> output type
 */
final class IsolateBlock<I, O> implements Block<I, O> {
  /** How often a waiting caller runs the owner's checks. */
  private static final long CHECK_MILLIS = 50;

  /** How long a caller that must wait spins, looking at {@link #serving}, before the monitor. */
  static final long SPIN_NANOS = TimeUnit.MICROSECONDS.toNanos(2);

  /** Looks at {@link #serving} between two reads of the clock while spinning. */
  private static final int SPINS_PER_CLOCK_READ = 16;

  private final Block<I, O> block;
  private final Runnable whileWaiting;
  private final BooleanSupplier callerGaveUp;
  private final long checkNanos;

  /** The ticket the next caller takes. */
  private final AtomicLong nextTicket = new AtomicLong();

  /** The ticket whose caller may run the block now (it may not have seen it yet). */
  private volatile long serving;

  /** Waiting callers wait on it; guards {@link #abandoned} and the writes of the counts below. */
  private final Object turns = new Object();

  /** Tickets of callers that gave up before their turn, skipped when it comes. */
  private final Set<Long> abandoned = new HashSet<>();

  /** The size of {@link #abandoned}, readable without the monitor (written under it). */
  private volatile int abandonedCount;

  /** How many callers wait on {@link #turns} (written under it). */
  private volatile int waiting;

  /**
   * The thread running the block now, or null; written only by that thread, around the block. A
   * plain field: a thread reads its own last write here or another thread's, never a stale write
   * of its own, so only a call from inside the block (which would wait for itself) sees itself.
   */
  private Thread running;

  /**
   * A shared block whose waiting callers stop only when interrupted.
   *
   * @param block the shared block
   */
  IsolateBlock(Block<I, O> block) {
    this(block, () -> {}, () -> false);
  }

  /**
   * @param block the shared block
   * @param whileWaiting runs repeatedly while a caller waits for its turn; throws to end the wait
   *     (the block is then not run for that caller)
   * @param callerGaveUp whether the caller of the call this thread runs gave up; asked while
   *     waiting and once after a wait (true: the block is not run for it)
   */
  IsolateBlock(Block<I, O> block, Runnable whileWaiting, BooleanSupplier callerGaveUp) {
    this(block, whileWaiting, callerGaveUp, TimeUnit.MILLISECONDS.toNanos(CHECK_MILLIS));
  }

  /**
   * Like the one above, with another interval between a waiter's checks (the stress tests use 0:
   * a waiter checks each time it looks at the turn, so a give-up meets every other step).
   *
   * @param checkNanos how long a waiter waits between its checks
   */
  IsolateBlock(
      Block<I, O> block, Runnable whileWaiting, BooleanSupplier callerGaveUp, long checkNanos) {
    this.block = Objects.requireNonNull(block, "isolated block must not be null");
    this.whileWaiting = Objects.requireNonNull(whileWaiting, "whileWaiting must not be null");
    this.callerGaveUp = Objects.requireNonNull(callerGaveUp, "callerGaveUp must not be null");
    this.checkNanos = checkNanos;
  }

  @Override
  public O process(I input) {
    Thread caller = Thread.currentThread();
    if (running == caller) {
      throw new IllegalStateException(
          "an isolated chain was called from inside itself, on the thread that runs it: the call"
              + " would wait for itself forever. Inside the shared block, call what it needs"
              + " directly, not through a user of its own isolated chain");
    }
    long ticket = nextTicket.getAndIncrement();
    boolean waits = serving != ticket;
    if (waits) {
      awaitTurn(ticket);
    }
    try {
      if (waits && callerGaveUp.getAsBoolean()) {
        throw gaveUp();
      }
      running = caller;
      try {
        return block.process(input);
      } finally {
        running = null;
      }
    } finally {
      passTurn(ticket);
    }
  }

  /** Waits until {@code ticket} is served; a caller that stops waiting gives its ticket up. */
  private void awaitTurn(long ticket) {
    if (spinUntilServed(ticket)) {
      return;
    }
    long nextCheck = System.nanoTime() + checkNanos;
    try {
      while (true) {
        synchronized (turns) {
          waiting++;
          try {
            long left;
            while (serving != ticket && (left = nextCheck - System.nanoTime()) > 0) {
              TimeUnit.NANOSECONDS.timedWait(turns, left);
            }
          } finally {
            waiting--;
          }
          if (serving == ticket) {
            return;
          }
        }
        whileWaiting.run();
        if (callerGaveUp.getAsBoolean()) {
          throw gaveUp();
        }
        nextCheck = System.nanoTime() + checkNanos;
      }
    } catch (InterruptedException e) {
      giveUp(ticket);
      Thread.currentThread().interrupt();
      throw new PrimeException("interrupted while waiting for the isolated chain to be free", e);
    } catch (RuntimeException | Error e) {
      giveUp(ticket);
      throw e;
    }
  }

  /**
   * Looks at {@link #serving} for up to {@link #SPIN_NANOS}: a turn that comes that soon is taken
   * without the monitor, and its finisher, seeing no waiter, does not enter it either. Reads only.
   *
   * @return whether {@code ticket} is served
   */
  private boolean spinUntilServed(long ticket) {
    long deadline = System.nanoTime() + SPIN_NANOS;
    int spins = 0;
    while (serving != ticket) {
      Thread.onSpinWait();
      if (++spins % SPINS_PER_CLOCK_READ == 0 && System.nanoTime() - deadline > 0) {
        return false;
      }
    }
    return true;
  }

  /** Ends the turn of {@code ticket}, whose caller ran the block or stopped at its turn. */
  private void passTurn(long ticket) {
    serving = ticket + 1;
    if (waiting > 0 || abandonedCount > 0) {
      synchronized (turns) {
        skipAbandonedAndWake();
      }
    }
  }

  /** Leaves the ticket of a caller that stopped waiting, to be skipped (at once if it is served). */
  private void giveUp(long ticket) {
    synchronized (turns) {
      abandoned.add(ticket);
      abandonedCount++;
      skipAbandonedAndWake(); // the turn may have come as this caller stopped waiting
    }
  }

  /** Under {@link #turns}: serves the next ticket whose caller still waits, and wakes the waiters. */
  private void skipAbandonedAndWake() {
    long served = serving;
    long next = served;
    while (abandonedCount > 0 && abandoned.remove(next)) {
      abandonedCount--;
      next++;
    }
    if (next != served) {
      serving = next; // the skipped turns had no owner: nobody else writes serving now
    }
    if (waiting > 0) {
      turns.notifyAll();
    }
  }

  private static PrimeException gaveUp() {
    return new PrimeException(
        "the caller gave up while this call waited for the isolated chain; it was not run");
  }
}
