package dev.prime.liberty;

import dev.prime.Block;
import dev.prime.ChainCompiler;
import dev.prime.NodeLogic;
import dev.prime.topology.TopologyNode;
import java.util.List;

/**
 * Compiles the topology model's chain nodes into steps: a chain made of a block is one step (its
 * block, named after the chain on failure), another core's chain is one unnamed step (its {@code
 * toBlock()}, which names its own failures), and a link joins the steps of its parts. Every other
 * template is the core's generic block, one step. A chain's block is one flat composition of all
 * its steps ({@link FlatComposition}): one invocation per block, no layer per link, no recursion.
 */
final class LibertyCompiler implements ChainCompiler<StepSequence> {

  @Override
  public Class<StepSequence> form() {
    return StepSequence.class;
  }

  @Override
  public StepSequence block(String chain, Block<?, ?> block) {
    return new Step(chain, block);
  }

  @Override
  public StepSequence foreign(String node, Block<?, ?> block) {
    return new Step(null, block);
  }

  /** A link joins the steps of both parts; other templates are the core's generic blocks. */
  @Override
  public StepSequence template(TopologyNode node, NodeLogic logic, List<StepSequence> parts) {
    return node instanceof TopologyNode.Link ? StepSequence.join(parts.get(0), parts.get(1)) : null;
  }

  @Override
  public Block<?, ?> toBlock(String chain, StepSequence form) {
    return FlatComposition.of(form.flatten());
  }
}
