package dev.prime;

import java.util.List;

/**
 * The logic of a repeater (logic layer): after each run of the inner chain it sees the input the
 * chain was given, the chain's output and the values its source published meanwhile, and decides
 * whether to run again (with which input) or stop (with which conclusion).
 *
 * @param <I> input type of the inner chain (and of the repeater chain)
 * @param <R> output type of the inner chain
 * @param <E> type of the collected source's values
 * @param <O> output type of the repeater chain: the conclusion
 * @see PrimeCore#repeater(Chain, Source, RepeaterBlock)
 */
@FunctionalInterface
public interface RepeaterBlock<I, R, E, O> {

  /**
   * @param input what the inner chain was given in this round
   * @param output what it returned
   * @param collected the values the source published since the previous round, oldest first
   *     (empty for a repeater without a source)
   * @return {@link Repeat#again(Object)} or {@link Repeat#stop(Object)}; never {@code null}
   */
  Repeat<I, O> next(I input, R output, List<E> collected);
}
