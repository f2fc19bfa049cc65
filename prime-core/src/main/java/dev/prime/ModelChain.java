package dev.prime;

import java.util.concurrent.atomic.AtomicBoolean;

/**
 * A chain of a core: the name of its node in the topology model and the form its media compiled
 * that node to. A link or template of the same core takes the form ({@link #formOf}); {@link
 * #toBlock()} asks the media for the block that runs it.
 *
 * <p>Design note (single use). A chain is claimed once: by {@link #toBlock()} or by the link or
 * template that takes it ({@link #claim()}). Both run under the core's declaration lock ({@link
 * DeclarationLock}), so a {@code toBlock()} on one thread and a link taking the same chain on
 * another never interleave between the link's checks and its claims: whichever comes second is
 * refused before it consumed anything.
 *
 * @param <I> input type
 * @param <O> output type
 * @param <F> the media's compiled form
 */
final class ModelChain<I, O, F> implements Chain<I, O> {
  private final PrimeCore core;
  private final String name;
  private final F form;
  private final ChainCompiler<F> media;
  private final AtomicBoolean used = new AtomicBoolean();

  ModelChain(PrimeCore core, String name, F form, ChainCompiler<F> media) {
    this.core = core;
    this.name = name;
    this.form = form;
    this.media = media;
  }

  @Override
  public PrimeCore core() {
    return core;
  }

  @Override
  public String name() {
    return name;
  }

  /**
   * Consumes the chain and returns its block, under the core's declaration lock; if the media
   * fails to make the block, the chain is unused again ({@link #unconsumeUnlessKept}). If the core
   * copies values ({@link CoreConfig#valueCopies()}) and the media does not already, the block
   * copies each input before the chain sees it and each result before the caller does: a call
   * crosses into the chain's service.
   */
  @Override
  public Block<I, O> toBlock() {
    return DeclarationLock.run(
        core,
        () -> {
          consume();
          Block<I, O> block;
          try {
            block = partBlock();
          } catch (RuntimeException | Error failed) {
            unconsumeUnlessKept(failed);
            throw failed;
          }
          ValueCodec copies = core.config().valueCopies();
          return copies == null || media.copiesValues()
              ? block
              : new CopyingBlock<>(name, block, copies);
        });
  }

  /**
   * The media failed to make this chain's block ({@link ChainCompiler#toBlock}), which leaves
   * nothing behind: the chain is unused again, so the same {@code toBlock()} can be made once the
   * cause is gone. Unless the media said it could not undo what it began, by a {@link
   * ChainAlreadyUsedException} naming this chain: the chain then stays consumed.
   */
  private void unconsumeUnlessKept(Throwable failed) {
    if (!ModelCompiler.isKept(name, failed)) {
      used.set(false);
    }
  }

  /**
   * Takes back the block {@link #toBlock()} made of this chain for a declaration of another core
   * (a template taking this chain as a part) that then failed, under that declaration's locks
   * (which include this core's): this core's media takes it back ({@link ChainCompiler#discard})
   * and the chain is unused again, so the declaration can be made again; if the media cannot, the
   * chain stays consumed. (Its {@code toBlock()} returned: a failure that names a chain is about
   * another one, perhaps of the same name in the declaring core.)
   */
  void giveBack() {
    if (media.discard(name, form)) {
      used.set(false);
    }
  }

  /** This chain's compiled form if it is a {@code type}, else {@code null}; consumes nothing. */
  <T> T formOf(Class<T> type) {
    return type.isInstance(form) ? type.cast(form) : null;
  }

  /**
   * Consumes this chain as a part of a link or template of its core that compiled (inside that
   * declaration).
   *
   * @throws ChainAlreadyUsedException if it was consumed before
   * @throws CoreClosedException if the core is closed
   */
  void claim() {
    consume();
  }

  /** {@return whether this chain was consumed} */
  boolean used() {
    return used.get();
  }

  /**
   * The block a generic template calls this chain through, once the template took it as a part.
   * It copies no values, even when the core copies them ({@link CoreConfig#valueCopies()}): a
   * template and its parts are one chain, in one service, and values between them stay there, as
   * they do between chains linked together (and as in a template a media fuses, such as
   * Radiant's).
   */
  @SuppressWarnings("unchecked")
  Block<I, O> partBlock() {
    return (Block<I, O>) media.toBlock(name, form);
  }

  private void consume() {
    if (core.isClosed()) {
      throw new CoreClosedException(core.name());
    }
    if (!used.compareAndSet(false, true)) {
      throw new ChainAlreadyUsedException(name);
    }
  }

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
    return "ModelChain[" + name + "]";
  }
}
