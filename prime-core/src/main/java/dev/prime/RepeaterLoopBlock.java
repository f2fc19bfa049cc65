package dev.prime;

import java.util.List;
import java.util.Objects;

/**
 * Runs an inner block in a loop: after each run, a collector gathers what a source published
 * meanwhile and a {@link RepeaterBlock} decides to run again (with a new input) or to stop (with a
 * conclusion, which this block returns).
 *
 * <p>The loop can always be stopped from outside: before every round after the first it checks
 * the calling thread's interrupt flag (if set, it stays set and a {@link PrimeException} ends the
 * call) and runs a check given by its owner (a core passes its open check, so closing the core
 * ends the loop with {@link dev.prime.CoreClosedException} within one round).
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

  /**
   * A loop that stops between rounds only when the calling thread is interrupted.
   *
   * @param inner the block that runs each round
   * @param collector returns the values gathered since its previous call; {@code null} for none
   * @param repeater decides after each round
   */
  RepeaterLoopBlock(
      Block<I, R> inner, Block<Token, List<E>> collector, RepeaterBlock<I, R, E, O> repeater) {
    this(inner, collector, repeater, () -> {});
  }

  /**
   * @param inner the block that runs each round
   * @param collector returns the values gathered since its previous call; {@code null} for none
   * @param repeater decides after each round
   * @param betweenRounds runs before every round after the first; throws to end the loop
   */
  RepeaterLoopBlock(
      Block<I, R> inner,
      Block<Token, List<E>> collector,
      RepeaterBlock<I, R, E, O> repeater,
      Runnable betweenRounds) {
    this.inner = Objects.requireNonNull(inner, "inner block must not be null");
    this.collector = collector;
    this.repeater = Objects.requireNonNull(repeater, "repeater block must not be null");
    this.betweenRounds = Objects.requireNonNull(betweenRounds, "betweenRounds must not be null");
  }

  @Override
  public O process(I input) {
    I round = input;
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
    }
  }
}
