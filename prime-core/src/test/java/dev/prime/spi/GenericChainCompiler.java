package dev.prime.spi;

import dev.prime.Block;
import dev.prime.ChainCompiler;

/**
 * The simplest {@link ChainCompiler}: a chain compiles to a block. A chain made of a block is that
 * block naming its failures ({@link FailureNamingBlock}); another core's chain is its own block;
 * every template is the core's generic block over its parts' blocks. For the core's own tests
 * (in its test sources, not a public SPI).
 */
public final class GenericChainCompiler implements ChainCompiler<Block<?, ?>> {

  /** The compiler; it keeps no state. */
  public GenericChainCompiler() {}

  @Override
  @SuppressWarnings({"unchecked", "rawtypes"})
  public Class<Block<?, ?>> form() {
    return (Class) Block.class;
  }

  @Override
  @SuppressWarnings({"unchecked", "rawtypes"})
  public Block<?, ?> block(String chain, Block<?, ?> block) {
    return new FailureNamingBlock(chain, block);
  }

  @Override
  public Block<?, ?> foreign(String node, Block<?, ?> block) {
    return block;
  }

  @Override
  public Block<?, ?> toBlock(String chain, Block<?, ?> form) {
    return form;
  }
}
