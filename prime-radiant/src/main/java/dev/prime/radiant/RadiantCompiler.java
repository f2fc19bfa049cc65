package dev.prime.radiant;

import dev.prime.Block;
import dev.prime.radiant.internal.FusedCompiler;
import dev.prime.radiant.internal.Node;
import dev.prime.ChainCompiler;
import dev.prime.NodeLogic;
import dev.prime.topology.TopologyNode;
import java.util.List;

/**
 * Compiles the topology model's chain nodes into Radiant's node trees: a chain made of a block
 * is a leaf, another core's chain an opaque node, and links, if/else, for-each, unions, forks and
 * guards become nodes over their parts' trees, which {@link FusedCompiler} turns into one class
 * when the chain becomes a block. Isolate's users, the collectors and the repeater are the core's
 * generic blocks, called from the fused class as leaves.
 */
final class RadiantCompiler implements ChainCompiler<Node> {

  @Override
  public Class<Node> form() {
    return Node.class;
  }

  @Override
  public Node block(String chain, Block<?, ?> block) {
    return new Node.Leaf(chain, block);
  }

  @Override
  public Node foreign(String node, Block<?, ?> block) {
    return new Node.Opaque(block);
  }

  @Override
  public Node template(TopologyNode node, NodeLogic logic, List<Node> parts) {
    String name = node.name();
    if (node instanceof TopologyNode.Link) {
      return new Node.Link(parts.get(0), parts.get(1));
    }
    if (node instanceof TopologyNode.IfElse) {
      return new Node.IfElse(
          name, ((NodeLogic.Condition) logic).condition(), parts.get(0), parts.get(1));
    }
    if (node instanceof TopologyNode.ForEach) {
      return new Node.ForEach(name, parts.get(0));
    }
    if (node instanceof TopologyNode.Union) {
      return new Node.Union(name, parts);
    }
    if (node instanceof TopologyNode.Fork) {
      return new Node.Fork(name, parts.get(0), ((NodeLogic.Events) logic).events());
    }
    if (node instanceof TopologyNode.Guard) {
      NodeLogic.Guarded guarded = (NodeLogic.Guarded) logic;
      return new Node.Guard(name, guarded.pass(), parts.get(0), guarded.substitute());
    }
    return null;
  }

  @Override
  public Block<?, ?> toBlock(String chain, Node form) {
    return FusedCompiler.compile(chain, form);
  }
}
