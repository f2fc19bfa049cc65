package dev.prime;

import dev.prime.spi.AbstractChain;
import dev.prime.spi.ChainCompiler;

/**
 * A chain of a core: the name of its node in the topology model and the form its media compiled
 * that node to. A link or template of the same core takes the form ({@link #compiledForm()});
 * {@link #toBlock()} asks the media for the block that runs it.
 *
 * @param <I> input type
 * @param <O> output type
 * @param <F> the media's compiled form
 */
final class ModelChain<I, O, F> extends AbstractChain<I, O> {
  private final F form;
  private final ChainCompiler<F> media;

  ModelChain(PrimeCore core, String name, F form, ChainCompiler<F> media) {
    super(core, name);
    this.form = form;
    this.media = media;
  }

  @Override
  protected Object compiledForm() {
    return form;
  }

  @Override
  @SuppressWarnings("unchecked")
  protected Block<I, O> createBlock() {
    return (Block<I, O>) media.toBlock(name(), form);
  }

  @Override
  protected boolean copiesValuesItself() {
    return media.copiesValues();
  }

  /**
   * This chain's compiled form if it is a {@code type}, else {@code null}; consumes nothing.
   */
  <T> T formOf(Class<T> type) {
    return type.isInstance(form) ? type.cast(form) : null;
  }

  /**
   * Consumes this chain as a part of a link or template of its core that compiled.
   *
   * @throws ChainAlreadyUsedException if it was consumed before
   * @throws CoreClosedException if the core is closed
   */
  void claim() {
    consume();
  }

  /** {@return whether this chain was consumed} */
  boolean used() {
    return isUsed();
  }

  /**
   * The block a generic template calls this chain through, once the template took it as a part:
   * what {@link #toBlock()} would have given.
   */
  Block<I, O> partBlock() {
    return copyingValues(createBlock());
  }
}
