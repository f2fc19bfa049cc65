package dev.prime;

import java.util.Objects;

/**
 * Feeds the output of one block to another: {@code second.process(first.process(x))}.
 *
 * @param <I> input type
 * @param <M> type passed between the blocks
 * @param <O> output type
 */
final class LinkBlock<I, M, O> implements Block<I, O> {
  private final Block<? super I, ? extends M> first;
  private final Block<? super M, ? extends O> second;

  /**
   * @param first runs first
   * @param second runs on the first block's output
   */
  LinkBlock(Block<? super I, ? extends M> first, Block<? super M, ? extends O> second) {
    this.first = Objects.requireNonNull(first, "first block must not be null");
    this.second = Objects.requireNonNull(second, "second block must not be null");
  }

  @Override
  public O process(I input) {
    return second.process(first.process(input));
  }
}
