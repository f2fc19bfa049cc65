package dev.prime;

import java.util.ArrayList;
import java.util.List;
import java.util.Objects;

/**
 * Runs a block on every element of a list, in order, and returns the list of outputs.
 *
 * @param <I> element type of the input list
 * @param <O> element type of the output list
 */
final class ForEachBlock<I, O> implements Block<List<I>, List<O>> {
  private final Block<I, O> body;

  /**
   * @param body runs once per element
   */
  ForEachBlock(Block<I, O> body) {
    this.body = Objects.requireNonNull(body, "body block must not be null");
  }

  @Override
  public List<O> process(List<I> input) {
    Objects.requireNonNull(input, "for-each input list must not be null");
    List<O> out = new ArrayList<>(input.size());
    for (I element : input) {
      out.add(body.process(element));
    }
    return out;
  }
}
