package dev.prime;

import java.util.Objects;

/**
 * Runs a block and also publishes each output to an event block (which a core may turn into a
 * source). {@code null} outputs are returned but not published.
 *
 * @param <I> input type
 * @param <O> output type
 */
final class ForkBlock<I, O> implements Block<I, O> {
  private final Block<I, O> block;
  private final EventBlock<? super O> events;

  /**
   * @param block computes the output
   * @param events receives a copy of every non-null output
   */
  ForkBlock(Block<I, O> block, EventBlock<? super O> events) {
    this.block = Objects.requireNonNull(block, "block must not be null");
    this.events = Objects.requireNonNull(events, "events must not be null");
  }

  @Override
  public O process(I input) {
    O output = block.process(input);
    if (output != null) {
      events.publish(output);
    }
    return output;
  }
}
