package dev.prime.liberty;

import dev.prime.Block;
import java.util.ArrayList;
import java.util.List;
import java.util.function.Function;

/**
 * Composes the steps of a linked chain into one block, in at most three tiers and without
 * recursion: up to {@link Runs#MAX_LENGTH} steps are one run; up to
 * {@link RunSequences#MAX_RUNS} runs are one sequence; longer chains are a {@link RunLoop} of
 * sequences. Every tier but the last is full, so each call site sees at most two classes.
 *
 * <p>Measured on the chain-length sweep (prime-bench/README.md): runs of 16 cost 1.0–1.4× the
 * FOR loop up to 64 blocks; runs of 8 in a loop cost 1.5–2×; one loop over all blocks (one call
 * site) costs 1.8× at 4 blocks and, in a JVM with many chains, as much as a megamorphic call per
 * block.
 */
final class FlatComposition {
  private FlatComposition() {}

  /**
   * The block that runs the steps in order.
   *
   * @param steps at least one step
   * @return the block
   */
  static Block<Object, Object> of(List<Step> steps) {
    if (steps.isEmpty()) {
      throw new IllegalArgumentException("a chain has at least one step");
    }
    List<Block<Object, Object>> runs = inGroups(steps, Runs.MAX_LENGTH, Runs::of);
    if (runs.size() == 1) {
      return runs.get(0);
    }
    List<Block<Object, Object>> sequences =
        inGroups(runs, RunSequences.MAX_RUNS, FlatComposition::sequence);
    return sequences.size() == 1 ? sequences.get(0) : new RunLoop(sequences);
  }

  private static Block<Object, Object> sequence(List<Block<Object, Object>> runs) {
    return runs.size() == 1 ? runs.get(0) : RunSequences.of(runs);
  }

  private static <T> List<Block<Object, Object>> inGroups(
      List<T> items, int size, Function<List<T>, Block<Object, Object>> group) {
    List<Block<Object, Object>> groups = new ArrayList<>();
    for (int from = 0; from < items.size(); from += size) {
      groups.add(group.apply(items.subList(from, Math.min(from + size, items.size()))));
    }
    return groups;
  }
}
