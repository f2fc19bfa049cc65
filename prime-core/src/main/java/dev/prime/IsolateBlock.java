package dev.prime;

import java.util.HashSet;
import java.util.Objects;
import java.util.Set;
import java.util.concurrent.TimeUnit;
import java.util.function.BooleanSupplier;

/**
 * Lets several callers share one block without ever running it concurrently: calls run one at a
 * time, in the order they came (first come, first served), so no caller starves.
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
 * <p>Design note: a ticket queue under one monitor. A caller takes the next ticket and waits on
 * the monitor, in slices of {@value #CHECK_MILLIS} ms for the checks, until the ticket being
 * served is its own; finishing serves the next ticket and wakes the waiters. A waiter that gives
 * up leaves its ticket in {@link #abandoned}, skipped when its turn comes (or serves the next one
 * itself, if its turn had just come). A waiter keeps its place while it runs a check, which a
 * lock taken with timed attempts would not (a timed-out attempt rejoins the queue at its tail).
 * The checks run outside the monitor and at most once per slice, however often waiters are woken.
 * Memory: two counters and the set of abandoned tickets still queued.
 *
 * @param <I> input type
 * @param <O> output type
 */
final class IsolateBlock<I, O> implements Block<I, O> {
  /** How often a waiting caller runs the owner's checks. */
  private static final long CHECK_MILLIS = 50;

  private final Block<I, O> block;
  private final Runnable whileWaiting;
  private final BooleanSupplier callerGaveUp;

  /** Guards the three fields below; waiting callers wait on it. */
  private final Object turns = new Object();

  /** The ticket the next caller takes. */
  private long nextTicket;

  /** The ticket whose caller may run the block now (it may not have seen it yet). */
  private long serving;

  /** Tickets of callers that gave up before their turn, skipped when it comes. */
  private final Set<Long> abandoned = new HashSet<>();

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
    this.block = Objects.requireNonNull(block, "isolated block must not be null");
    this.whileWaiting = Objects.requireNonNull(whileWaiting, "whileWaiting must not be null");
    this.callerGaveUp = Objects.requireNonNull(callerGaveUp, "callerGaveUp must not be null");
  }

  @Override
  public O process(I input) {
    long ticket;
    boolean waits;
    synchronized (turns) {
      ticket = nextTicket++;
      waits = ticket != serving;
    }
    if (waits) {
      awaitTurn(ticket);
    }
    try {
      if (waits && callerGaveUp.getAsBoolean()) {
        throw gaveUp();
      }
      return block.process(input);
    } finally {
      synchronized (turns) {
        serveNext();
      }
    }
  }

  /** Waits until {@code ticket} is served; a caller that stops waiting gives its ticket up. */
  private void awaitTurn(long ticket) {
    long nextCheck = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(CHECK_MILLIS);
    try {
      while (true) {
        synchronized (turns) {
          if (serving == ticket) {
            return;
          }
          long left = nextCheck - System.nanoTime();
          if (left > 0) {
            TimeUnit.NANOSECONDS.timedWait(turns, left);
            continue;
          }
        }
        whileWaiting.run();
        if (callerGaveUp.getAsBoolean()) {
          throw gaveUp();
        }
        nextCheck = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(CHECK_MILLIS);
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

  private void giveUp(long ticket) {
    synchronized (turns) {
      if (serving == ticket) {
        serveNext(); // the turn came as this caller stopped waiting: pass it on
      } else {
        abandoned.add(ticket);
      }
    }
  }

  /** Serves the next ticket whose caller still waits, and wakes the waiters. Under {@link #turns}. */
  private void serveNext() {
    serving++;
    while (!abandoned.isEmpty() && abandoned.remove(serving)) {
      serving++;
    }
    turns.notifyAll();
  }

  private static PrimeException gaveUp() {
    return new PrimeException(
        "the caller gave up while this call waited for the isolated chain; it was not run");
  }
}
