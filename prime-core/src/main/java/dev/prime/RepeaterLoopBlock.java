package dev.prime;

import java.util.List;
import java.util.Objects;
import java.util.concurrent.TimeUnit;
import java.util.function.BooleanSupplier;

/**
 * Runs an inner block in a loop: after each run, a collector gathers what a source published
 * meanwhile and a {@link RepeaterBlock} decides to run again (with a new input) or to stop (with a
 * conclusion, which this block returns).
 *
 * <p>The loop can always be stopped from outside: before every round after the first it checks
 * the calling thread's interrupt flag (if set, it stays set and a {@link PrimeException} ends the
 * call) and runs a check given by its owner (a core passes its open check, so closing the core
 * ends the loop with {@link dev.prime.CoreClosedException} within one round). Where the loop runs
 * on a service's thread for a caller elsewhere (Optimus), the owner also says whether that caller
 * gave up ({@link PrimeCore#callerGaveUp}): asked between rounds, at most once every {@value
 * #CHECK_MILLIS} ms of the loop (so a loop of short rounds does not ask Redis each round), a yes
 * ends the loop with a {@link PrimeException}, and the service goes on to its next call.
 *
 * @param <I> input type of the inner block and of this block
 * @param <R> output type of the inner block
 * @param <E> type of the collected values
 * @param <O> output type: the conclusion
 */
final class RepeaterLoopBlock<I, R, E, O> implements Block<I, O> {
  private final Block<I, R> inner;
  private final Block<Token, List<E>> collector;
  private final RepeaterBlock<I, R, E, O> repeater;
  private final Runnable betweenRounds;
  private final BooleanSupplier callerGaveUp; // null: callers run the loop on their own threads

  /** How often, at most, the loop asks whether its caller gave up. */
  private static final long CHECK_MILLIS = 50;

  /**
   * A loop that stops between rounds only when the calling thread is interrupted.
   *
   * @param inner the block that runs each round
   * @param collector returns the values gathered since its previous call; {@code null} for none
   * @param repeater decides after each round
   */
  RepeaterLoopBlock(
      Block<I, R> inner, Block<Token, List<E>> collector, RepeaterBlock<I, R, E, O> repeater) {
    this(inner, collector, repeater, () -> {}, null);
  }

  /**
   * @param inner the block that runs each round
   * @param collector returns the values gathered since its previous call; {@code null} for none
   * @param repeater decides after each round
   * @param betweenRounds runs before every round after the first; throws to end the loop
   * @param callerGaveUp whether the caller of the call this thread runs gave up; asked between
   *     rounds, at most every {@value #CHECK_MILLIS} ms; {@code null} where callers run the loop
   *     on their own threads
   */
  RepeaterLoopBlock(
      Block<I, R> inner,
      Block<Token, List<E>> collector,
      RepeaterBlock<I, R, E, O> repeater,
      Runnable betweenRounds,
      BooleanSupplier callerGaveUp) {
    this.inner = Objects.requireNonNull(inner, "inner block must not be null");
    this.collector = collector;
    this.repeater = Objects.requireNonNull(repeater, "repeater block must not be null");
    this.betweenRounds = Objects.requireNonNull(betweenRounds, "betweenRounds must not be null");
    this.callerGaveUp = callerGaveUp;
  }

  @Override
  public O process(I input) {
    I round = input;
    long nextCheck = callerGaveUp == null ? 0 : System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(CHECK_MILLIS);
    while (true) {
      R output = inner.process(round);
      List<E> collected = collector == null ? List.of() : collector.process(Token.INSTANCE);
      Repeat<I, O> decision = repeater.next(round, output, collected);
      if (decision == null) {
        throw new NullPointerException(
            "the repeater block returned null; return Repeat.again(next) or Repeat.stop(result)");
      }
      if (!decision.isAgain()) {
        return decision.conclusion();
      }
      round = decision.next();
      if (Thread.currentThread().isInterrupted()) {
        throw new PrimeException("interrupted between two rounds of a repeater");
      }
      betweenRounds.run();
      if (callerGaveUp != null) {
        long now = System.nanoTime();
        if (now - nextCheck >= 0) {
          if (callerGaveUp.getAsBoolean()) {
            throw new PrimeException(
                "the caller gave up (its timeout passed, or it was interrupted): the repeater"
                    + " stopped");
          }
          nextCheck = now + TimeUnit.MILLISECONDS.toNanos(CHECK_MILLIS);
        }
      }
    }
  }
}
