package dev.prime.liberty;

import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.List;

/**
 * The steps of a Liberty chain while it is being linked: a step, or two sequences one after the
 * other. Linking costs one object whatever the lengths; {@link #flatten()} turns the tree into
 * the list of steps once, when the chain becomes a block, without recursion, so chains of any
 * length and any link order (left, right, balanced) build in time and stack proportional to
 * nothing but their number of steps.
 */
sealed interface StepSequence permits Step, StepSequence.Joined {

  /**
   * The steps of {@code first} followed by those of {@code second}.
   *
   * @param first runs first
   * @param second runs on its outputs
   * @return the joined sequence
   */
  static StepSequence join(StepSequence first, StepSequence second) {
    return new Joined(first, second);
  }

  /**
   * The steps in order.
   *
   * @return a new list
   */
  default List<Step> flatten() {
    List<Step> steps = new ArrayList<>();
    ArrayDeque<StepSequence> pending = new ArrayDeque<>();
    pending.push(this);
    while (!pending.isEmpty()) {
      StepSequence next = pending.pop();
      if (next instanceof Joined joined) {
        pending.push(joined.second());
        pending.push(joined.first());
      } else {
        steps.add((Step) next);
      }
    }
    return steps;
  }

  /**
   * Two sequences, one after the other.
   *
   * @param first runs first
   * @param second runs on its outputs
   */
  record Joined(StepSequence first, StepSequence second) implements StepSequence {}
}
