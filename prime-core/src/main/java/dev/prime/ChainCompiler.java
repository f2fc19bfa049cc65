package dev.prime;

import dev.prime.topology.TopologyNode;
import java.util.List;

/**
 * How a media compiles the chain nodes of the topology model into its own form {@code F} (Liberty:
 * steps of a flat composition; Radiant: a node tree fused into one class; Optimus: the services a
 * chain is made of). A media gives the core one compiler ({@code PrimeCore.chainCompiler()}); the
 * core records each chain the program declares as a {@link TopologyNode} with its {@link
 * NodeLogic} and, at once, compiles it from that node, that logic and the compiled forms of its
 * parts, bottom-up: a part is always compiled before the node that uses it, so nothing walks the
 * model recursively and a chain of any length compiles in time proportional to its size.
 *
 * <p>A media compiles what it can do better ({@link #template}: Radiant fuses links, if/else,
 * for-each, unions, forks and guards; Liberty and Optimus join the parts of a link); every other
 * node (a template it leaves alone, isolate's users, the collectors, the repeater) the core
 * compiles once for every media, into the template's generic block (written once, in the core)
 * over the blocks of its parts ({@link #toBlock}), which it gives to {@link #block}. The templates
 * are therefore described in one place: the model node, its logic and that generic block.
 *
 * @param <F> the media's compiled form of a chain
 */
public interface ChainCompiler<F> {

  /** {@return the class of the compiled form (checked when a chain's form is taken as a part)} */
  Class<F> form();

  /**
   * Compiles a chain that runs a block: a {@link TopologyNode.BlockChain} (the user's block) or
   * a node the core compiled to a generic block. What the block throws must reach a caller as a
   * {@link dev.prime.ChainFailedException} naming {@code chain} (see {@link dev.prime.spi.FailureNamingBlock}).
   *
   * @param chain the node's name
   * @param block the block
   * @return the compiled form
   */
  F block(String chain, Block<?, ?> block);

  /**
   * Compiles a {@link TopologyNode.ForeignChain}: another core's chain, taken through its
   * {@link dev.prime.Chain#toBlock()} (whose block names its own failures).
   *
   * @param node the foreign node's name ({@code hosted(name)})
   * @param block the other chain's block
   * @return the compiled form
   */
  F foreign(String node, Block<?, ?> block);

  /**
   * Compiles a template node in this media's own way, or declines.
   *
   * @param node the template node ({@link TopologyNode.Link}, {@link TopologyNode.IfElse}, {@link
   *     TopologyNode.ForEach}, {@link TopologyNode.Union}, {@link TopologyNode.Fork} or {@link
   *     TopologyNode.Guard})
   * @param logic its logic
   * @param parts the compiled forms of the chains it runs, in the order of {@link
   *     TopologyNode#parts()}
   * @return the compiled form, or {@code null} (the default) to have the core compile the
   *     template's generic block over its parts' blocks and give it to {@link #block}
   */
  default F template(TopologyNode node, NodeLogic logic, List<F> parts) {
    return null;
  }

  /**
   * The block that runs a compiled chain: what {@link dev.prime.Chain#toBlock()} gives and what
   * a generic template calls its parts through.
   *
   * <p>If it throws, it must leave nothing behind (a media that starts services for the chain
   * stops and forgets those it started): the core then leaves the chain unused, so that the
   * program can make the same {@code toBlock()} again once the cause is gone. A media that cannot
   * undo what it began throws a {@link ChainAlreadyUsedException} naming {@code chain}, made with
   * {@link ChainAlreadyUsedException#ChainAlreadyUsedException(String, String, Throwable)}, which
   * says why; the chain then stays consumed.
   *
   * @param chain the chain's name
   * @param form its compiled form
   * @return the block
   */
  Block<?, ?> toBlock(String chain, F form);

  /**
   * Takes back the block {@link #toBlock} made for {@code chain} as a part of a declaration that
   * then failed (a template whose other part failed, for instance): that block will never be
   * called, and the chain stays unused, so a media that started services for it stops and forgets
   * them, as a {@code toBlock} that fails does. Also called for a part whose block was not made
   * (then there is nothing to take back).
   *
   * @param chain the part's chain name
   * @param form its compiled form
   * @return whether nothing of the block is left (the default); {@code false} if the media could
   *     not take it back, and the chain then stays consumed
   */
  default boolean discard(String chain, F form) {
    return true;
  }

  /**
   * Whether this media's blocks already copy every input and result (as a media that carries
   * them between processes does), so that {@link dev.prime.CoreConfig#valueCopies()} adds
   * nothing.
   *
   * @return false by default
   */
  default boolean copiesValues() {
    return false;
  }
}
