package dev.prime;

import java.util.Objects;
import java.util.function.Predicate;

/**
 * Runs a block only for inputs that pass a predicate; the others short-circuit to a substitute.
 *
 * @param <I> input type
 * @param <O> output type
 */
final class GuardBlock<I, O> implements Block<I, O> {
  private final Predicate<? super I> pass;
  private final Block<I, O> block;
  private final Block<? super I, ? extends O> substitute;

  /**
   * @param pass inputs that pass run {@code block}
   * @param block the guarded block
   * @param substitute computes the output for inputs that do not pass
   */
  GuardBlock(
      Predicate<? super I> pass, Block<I, O> block, Block<? super I, ? extends O> substitute) {
    this.pass = Objects.requireNonNull(pass, "guard predicate must not be null");
    this.block = Objects.requireNonNull(block, "guarded block must not be null");
    this.substitute = Objects.requireNonNull(substitute, "substitute block must not be null");
  }

  @Override
  public O process(I input) {
    return pass.test(input) ? block.process(input) : substitute.process(input);
  }
}
