package dev.prime.liberty;

import dev.prime.Block;
import dev.prime.spi.FailureNamingBlock;
import java.util.Objects;

/**
 * One block of a flattened Liberty chain and the chain to name when it fails.
 *
 * <p>A step of this core's own chain names that chain, exactly as a {@link FailureNamingBlock}
 * would: on failure the throwable is handed to one, so what a caller receives for each kind of
 * throwable is defined in one place for every media. A step taken from another core's chain
 * (through its {@code toBlock()}) has no name: that block names its own failures, and what it
 * throws passes unchanged.
 */
final class Step implements StepSequence {
  private final String chainName;
  private final Block<Object, Object> block;

  /**
   * @param chainName the chain to name on failure, or null if the block names its own failures
   * @param block the block
   */
  @SuppressWarnings("unchecked")
  Step(String chainName, Block<?, ?> block) {
    this.chainName = chainName;
    this.block = (Block<Object, Object>) Objects.requireNonNull(block, "block");
  }

  /** The block, to be called directly. */
  Block<Object, Object> block() {
    return block;
  }

  /**
   * What the caller receives when this step's block threw {@code failure}: never returns
   * normally (it throws), declared to return so that callers can write {@code throw failed(e)}.
   *
   * @param failure what the block threw
   * @return never
   */
  RuntimeException failed(Throwable failure) {
    if (chainName != null) {
      new FailureNamingBlock<Object, Object>(chainName, input -> rethrow(failure)).process(null);
    }
    throw Step.<RuntimeException>sneaky(failure);
  }

  private static Object rethrow(Throwable failure) {
    throw Step.<RuntimeException>sneaky(failure);
  }

  /** Throws any throwable without declaring it (the block threw it, so it may pass on). */
  @SuppressWarnings("unchecked")
  private static <T extends Throwable> T sneaky(Throwable failure) throws T {
    throw (T) failure;
  }
}
