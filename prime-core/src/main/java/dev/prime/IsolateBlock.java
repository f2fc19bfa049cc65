package dev.prime;

import java.util.Objects;
import java.util.concurrent.TimeUnit;
import java.util.function.BooleanSupplier;
import java.util.concurrent.locks.ReentrantLock;

/**
 * Lets several callers share one block without ever running it concurrently: calls are
 * serialised by a fair lock, so no caller starves.
 *
 * <p>A caller waiting for its turn honours interruption: it stops waiting, keeps its interrupt
 * flag set and gets a {@link PrimeException}; the block is not run for it. A waiting caller also
 * runs a check given by the owner every {@value #CHECK_MILLIS} ms (a core passes its open check,
 * so closing the core ends the wait with {@link dev.prime.CoreClosedException}). Where the block
 * runs on a service's thread for a caller elsewhere (Optimus), the owner also says whether that
 * caller gave up ({@link PrimeCore#callerGaveUp}): asked every {@value #CHECK_MILLIS} ms of the
 * wait and once when the turn comes after a wait (never when the lock was free), a yes ends the
 * wait with a {@link PrimeException}, and the block is not run for that call either.
 *
 * <p>Design note: the lock is taken in slices of {@value #CHECK_MILLIS} ms so the checks run
 * while waiting; a waiter out of the lock's queue for a check rejoins at its tail.
 *
 * @param <I> input type
 * @param <O> output type
 */
final class IsolateBlock<I, O> implements Block<I, O> {
  private final Block<I, O> block;
  /** How often a waiting caller runs the owner's checks. */
  private static final long CHECK_MILLIS = 50;

  private final ReentrantLock lock = new ReentrantLock(true);
  private final Runnable whileWaiting;
  private final BooleanSupplier callerGaveUp;

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
    boolean waited = lock.isLocked() || lock.hasQueuedThreads(); // a free lock: no wait, nothing to ask
    try {
      while (!lock.tryLock(CHECK_MILLIS, TimeUnit.MILLISECONDS)) {
        waited = true;
        whileWaiting.run();
        if (callerGaveUp.getAsBoolean()) {
          throw gaveUp();
        }
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new PrimeException("interrupted while waiting for the isolated chain to be free", e);
    }
    try {
      if (waited && callerGaveUp.getAsBoolean()) {
        throw gaveUp();
      }
      return block.process(input);
    } finally {
      lock.unlock();
    }
  }

  private static PrimeException gaveUp() {
    return new PrimeException(
        "the caller gave up while this call waited for the isolated chain; it was not run");
  }
}
