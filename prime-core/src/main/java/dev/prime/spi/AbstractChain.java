package dev.prime.spi;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
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

  @Override
  public final Block<I, O> toBlock() {
    consume();
    return createBlock();
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

  /** {@return whether this chain was consumed} */
  public final boolean isUsed() {
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

  @Override
  public String toString() {
    return getClass().getSimpleName() + "[" + name + "]";
  }
}
