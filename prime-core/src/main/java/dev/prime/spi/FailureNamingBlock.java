package dev.prime.spi;

import dev.prime.Block;
import dev.prime.ChainFailedException;
import dev.prime.CoreClosedException;
import java.util.Objects;

/**
 * Wraps a chain's block so that what it throws reaches the caller as a
 * {@link ChainFailedException} naming the chain, with the block's own throwable as cause: any
 * exception, checked ones thrown sneakily included, and any {@link Error} but a
 * {@link VirtualMachineError}, which passes unchanged (the JVM itself is in trouble). Exceptions
 * that already are {@code ChainFailedException} (an inner chain failed) or
 * {@link CoreClosedException} pass unchanged too, so the innermost failing chain is the one named.
 *
 * @param <I> input type
 * @param <O> output type
 */
public final class FailureNamingBlock<I, O> implements Block<I, O> {
  private final String chainName;
  private final Block<I, O> block;

  /**
   * @param chainName the chain to name on failure
   * @param block the block to run
   */
  public FailureNamingBlock(String chainName, Block<I, O> block) {
    this.chainName = Objects.requireNonNull(chainName, "chainName");
    this.block = Objects.requireNonNull(block, "block");
  }

  @Override
  public O process(I input) {
    try {
      return block.process(input);
    } catch (ChainFailedException | CoreClosedException | VirtualMachineError e) {
      throw e;
    } catch (Throwable e) {
      throw new ChainFailedException(chainName, e);
    }
  }

  /** {@return the wrapped block} */
  public Block<I, O> unwrap() {
    return block;
  }

  /** {@return the name of the chain} */
  public String chainName() {
    return chainName;
  }
}
