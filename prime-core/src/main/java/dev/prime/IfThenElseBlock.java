package dev.prime;

import java.util.Objects;
import java.util.function.Predicate;

/**
 * Routes each input to one of two blocks by a condition.
 *
 * @param <I> input type
 * @param <O> output type
 */
final class IfThenElseBlock<I, O> implements Block<I, O> {
  private final Predicate<? super I> condition;
  private final Block<I, O> then;
  private final Block<I, O> otherwise;

  /**
   * @param condition chooses the branch
   * @param then runs when the condition holds
   * @param otherwise runs when it does not
   */
  IfThenElseBlock(Predicate<? super I> condition, Block<I, O> then, Block<I, O> otherwise) {
    this.condition = Objects.requireNonNull(condition, "condition must not be null");
    this.then = Objects.requireNonNull(then, "then block must not be null");
    this.otherwise = Objects.requireNonNull(otherwise, "otherwise block must not be null");
  }

  @Override
  public O process(I input) {
    return condition.test(input) ? then.process(input) : otherwise.process(input);
  }
}
