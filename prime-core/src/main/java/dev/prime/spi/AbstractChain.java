package dev.prime.spi;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
import dev.prime.ChainFailedException;
import dev.prime.CoreClosedException;
import dev.prime.PrimeCore;
import java.util.Objects;
import java.util.concurrent.atomic.AtomicBoolean;

/**
 * Base of media chains: holds the core and the name, and enforces single use.
 *
 * @param <I> input type
 * @param <O> output type
 */
public abstract class AbstractChain<I, O> implements Chain<I, O> {
  private final PrimeCore core;
  private final String name;
  private final AtomicBoolean used = new AtomicBoolean();

  /**
   * @param core the owning core
   * @param name the chain's unique name in that core
   */
  protected AbstractChain(PrimeCore core, String name) {
    this.core = Objects.requireNonNull(core, "core");
    this.name = Objects.requireNonNull(name, "name");
  }

  @Override
  public final PrimeCore core() {
    return core;
  }

  @Override
  public final String name() {
    return name;
  }

  /**
   * Consumes the chain and returns its block. If the core copies values
   * ({@link dev.prime.CoreConfig#valueCopies()}) and {@link #copiesValuesItself()} is false, the
   * block copies each input before the chain sees it and each result before the caller does.
   */
  @Override
  public final Block<I, O> toBlock() {
    consume();
    return copyingValues(createBlock());
  }

  /**
   * {@code block} as {@link #toBlock()} hands it out: copying each input and result if the core
   * copies values and this media does not already ({@link #copiesValuesItself()}).
   *
   * @param block a block of this chain
   * @return {@code block}, or a block that copies around it
   */
  protected final Block<I, O> copyingValues(Block<I, O> block) {
    ValueCodec copies = core.config().valueCopies();
    return copies == null || copiesValuesItself() ? block : new CopyingBlock<>(name, block, copies);
  }

  /**
   * Whether this media's blocks already copy every input and result (as a media that carries
   * them between processes does), so that {@link dev.prime.CoreConfig#valueCopies()} adds
   * nothing. False by default.
   *
   * @return true if values never cross this chain by reference
   */
  protected boolean copiesValuesItself() {
    return false;
  }

  /**
   * Marks this chain consumed. A media calls it when it links the chain without
   * {@link #toBlock()}.
   *
   * @throws ChainAlreadyUsedException if it was consumed before
   * @throws CoreClosedException if the core is closed
   */
  protected final void consume() {
    if (core.isClosed()) {
      throw new CoreClosedException(core.name());
    }
    if (!used.compareAndSet(false, true)) {
      throw new ChainAlreadyUsedException(name);
    }
  }

  /**
   * What this media compiled the chain to, that a link or template of the same core takes in
   * place of {@link #toBlock()} (Radiant: the chain's node tree; Optimus: its services); {@code
   * null} (the default) if the media has no such form. See {@link ChainCompiler}.
   *
   * @return the compiled form, or {@code null}
   */
  protected Object compiledForm() {
    return null;
  }

  /** {@return whether this chain was consumed} */
  protected final boolean isUsed() {
    return used.get();
  }

  /**
   * Creates the block that runs this chain; called once, by {@link #toBlock()}. Failures of the
   * blocks inside must reach the caller as {@link dev.prime.ChainFailedException} (see
   * {@link FailureNamingBlock}).
   *
   * @return the block
   */
  protected abstract Block<I, O> createBlock();

  /** A synchronous call that copies its input and its result, like a call between processes. */
  private static final class CopyingBlock<I, O> implements Block<I, O> {
    private final String chainName;
    private final Block<I, O> block;
    private final ValueCodec copies;

    CopyingBlock(String chainName, Block<I, O> block, ValueCodec copies) {
      this.chainName = chainName;
      this.block = block;
      this.copies = copies;
    }

    @Override
    public O process(I input) {
      O result = block.process(copies.copy(input));
      try {
        return copies.copy(result);
      } catch (RuntimeException e) {
        throw new ChainFailedException(chainName, e); // the result could not leave the service
      }
    }
  }

  @Override
  public String toString() {
    return getClass().getSimpleName() + "[" + name + "]";
  }
}
