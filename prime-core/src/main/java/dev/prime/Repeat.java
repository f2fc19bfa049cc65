package dev.prime;

import java.util.Objects;

/**
 * What a {@link RepeaterBlock} decides after one run of the inner chain: run again with a new
 * input, or stop with a conclusion.
 *
 * @param <I> input type of the inner chain
 * @param <O> type of the conclusion
 */
public final class Repeat<I, O> {
  private final boolean again;
  private final I next;
  private final O conclusion;

  private Repeat(boolean again, I next, O conclusion) {
    this.again = again;
    this.next = next;
    this.conclusion = conclusion;
  }

  /**
   * Run the inner chain again.
   *
   * @param next its next input
   * @param <I> input type of the inner chain
   * @param <O> type of the conclusion
   * @return the decision
   */
  public static <I, O> Repeat<I, O> again(I next) {
    return new Repeat<>(true, next, null);
  }

  /**
   * Stop; the repeater chain returns {@code conclusion}.
   *
   * @param conclusion the repeater chain's output
   * @param <I> input type of the inner chain
   * @param <O> type of the conclusion
   * @return the decision
   */
  public static <I, O> Repeat<I, O> stop(O conclusion) {
    return new Repeat<>(false, null, conclusion);
  }

  /** {@return whether the inner chain runs again} */
  public boolean isAgain() {
    return again;
  }

  /** {@return the next input of the inner chain; only meaningful if {@link #isAgain()}} */
  public I next() {
    return next;
  }

  /** {@return the conclusion; only meaningful if not {@link #isAgain()}} */
  public O conclusion() {
    return conclusion;
  }

  @Override
  public boolean equals(Object o) {
    return o instanceof Repeat<?, ?> r
        && again == r.again
        && Objects.equals(next, r.next)
        && Objects.equals(conclusion, r.conclusion);
  }

  @Override
  public int hashCode() {
    return Objects.hash(again, next, conclusion);
  }

  @Override
  public String toString() {
    return again ? "Repeat.again(" + next + ")" : "Repeat.stop(" + conclusion + ")";
  }
}
