package dev.prime.topology;

import java.util.ArrayList;
import java.util.Collection;
import java.util.Collections;
import java.util.HashMap;
import java.util.LinkedHashSet;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.Set;
import java.util.TreeMap;
import java.util.TreeSet;

/**
 * An immutable snapshot of the diagram declared on a core: its {@linkplain #nodes() nodes} in
 * declaration order, which of them are {@linkplain #services() services} (see {@link
 * TopologyNode}), and which services this process does not host ({@link #hostedElsewhere()}:
 * only a media that spreads services over processes, Optimus, has any).
 *
 * <p>The same declarations give an equal topology, and the same {@link #toMermaid()} and {@link
 * #toDot()} text, on every media. The core's own name is not part of it.
 *
 * <pre>{@code
 * Topology topology = core.topology();
 * System.out.println(topology.toMermaid()); // paste into a Markdown ```mermaid block
 * }</pre>
 */
public final class Topology {
  private final List<TopologyNode> nodes;
  private final Map<String, TopologyNode> byName;
  private final Set<String> services;
  private final Set<String> hostedElsewhere;
  private final Map<String, String> pseudonames;

  private Topology(
      List<TopologyNode> nodes, Set<String> hostedElsewhere, Map<String, String> pseudonames) {
    this.nodes = List.copyOf(nodes);
    Map<String, TopologyNode> index = new HashMap<>();
    Set<String> serviceNames = new LinkedHashSet<>();
    for (TopologyNode node : this.nodes) {
      for (TopologyNode.Part part : node.parts()) {
        if (!index.containsKey(part.node())) {
          throw new IllegalArgumentException(
              "node '" + node.name() + "' uses '" + part.node() + "', which is not declared"
                  + " before it");
        }
      }
      if (index.putIfAbsent(node.name(), node) != null) {
        throw new IllegalArgumentException("two nodes are named '" + node.name() + "'");
      }
      if (node.isService()) {
        serviceNames.add(node.name());
      }
    }
    for (String service : hostedElsewhere) {
      if (!serviceNames.contains(service)) {
        throw new IllegalArgumentException(
            "'" + service + "' is said to be hosted elsewhere but is not a service of this"
                + " topology; its services: " + serviceNames);
      }
    }
    this.byName = index;
    this.services = Collections.unmodifiableSet(serviceNames);
    this.hostedElsewhere = Collections.unmodifiableSet(new TreeSet<>(hostedElsewhere));
    for (String named : pseudonames.keySet()) {
      if (!index.containsKey(named)) {
        throw new IllegalArgumentException(
            "'" + named + "' has a pseudoname but is not a node of this topology");
      }
    }
    this.pseudonames = Collections.unmodifiableMap(new TreeMap<>(pseudonames));
  }

  /**
   * A topology of {@code nodes}.
   *
   * @param nodes in declaration order; each node's parts must come before it
   * @param hostedElsewhere the services this process does not run (empty: it runs all)
   * @return the topology
   * @throws IllegalArgumentException if a name is used twice, a part is not declared before the
   *     node using it, or a name in {@code hostedElsewhere} is not a service
   */
  public static Topology of(List<TopologyNode> nodes, Collection<String> hostedElsewhere) {
    return new Topology(nodes, new LinkedHashSet<>(hostedElsewhere), Map.of());
  }

  /**
   * A topology of {@code nodes} whose chains and sources may have pseudonames.
   *
   * @param nodes in declaration order; each node's parts must come before it
   * @param hostedElsewhere the services this process does not run (empty: it runs all)
   * @param pseudonames readable names by node name (see {@link #pseudoname(String)})
   * @return the topology
   * @throws IllegalArgumentException as {@link #of(List, Collection)}, or if a pseudoname names
   *     no node
   */
  public static Topology of(
      List<TopologyNode> nodes, Collection<String> hostedElsewhere, Map<String, String> pseudonames) {
    return new Topology(nodes, new LinkedHashSet<>(hostedElsewhere), Map.copyOf(pseudonames));
  }

  /**
   * The pseudoname of a node: the readable name the user gave a chain or source at creation
   * ({@code core.chain("odometry", "Wheel odometry", block)}), shown in the drawings and the
   * recordings next to the node's name.
   *
   * @param name a node's name
   * @return its pseudoname, or empty if it has none
   */
  public Optional<String> pseudoname(String name) {
    return Optional.ofNullable(pseudonames.get(name));
  }

  /** {@return the pseudonames by node name, sorted by name} */
  public Map<String, String> pseudonames() {
    return pseudonames;
  }

  /** {@return every node, in declaration order} */
  public List<TopologyNode> nodes() {
    return nodes;
  }

  /**
   * The node with a name.
   *
   * @param name a chain's, source's, service's or reader's name
   * @return the node, or empty if there is none
   */
  public Optional<TopologyNode> node(String name) {
    return Optional.ofNullable(byName.get(name));
  }

  /** {@return the names of the services, in declaration order (see {@link TopologyNode})} */
  public Set<String> services() {
    return services;
  }

  /** {@return the services this process does not run, sorted; empty when it runs all of them} */
  public Set<String> hostedElsewhere() {
    return hostedElsewhere;
  }

  /**
   * Whether this process runs a service.
   *
   * @param service a service's name
   * @return true if it is a service of this topology hosted here
   */
  public boolean isHostedHere(String service) {
    return services.contains(service) && !hostedElsewhere.contains(service);
  }

  /**
   * The diagram as a Mermaid flowchart. Chains are boxes, templates hexagons, sources stadiums
   * and cylinders, readers circles, generic services double-sided boxes; solid arrows carry
   * values, dashed arrows go from a template to the chains it runs, labelled with their role;
   * services hosted elsewhere are dashed. A node with a {@linkplain #pseudoname(String)
   * pseudoname} is labelled {@code pseudoname (name)}. Deterministic: the same topology always
   * gives the same text.
   *
   * @return the flowchart, ending with a newline
   */
  public String toMermaid() {
    return new Drawing(this).mermaid();
  }

  /**
   * The diagram as a Graphviz DOT digraph, drawn like {@link #toMermaid()}.
   *
   * @return the digraph, ending with a newline
   */
  public String toDot() {
    return new Drawing(this).dot();
  }

  /** Two topologies are equal when they have equal nodes in the same order and host alike. */
  @Override
  public boolean equals(Object other) {
    return other instanceof Topology that
        && nodes.equals(that.nodes)
        && hostedElsewhere.equals(that.hostedElsewhere)
        && pseudonames.equals(that.pseudonames);
  }

  @Override
  public int hashCode() {
    return nodes.hashCode() * 31 + hostedElsewhere.hashCode();
  }

  @Override
  public String toString() {
    List<String> names = new ArrayList<>(nodes.size());
    nodes.forEach(node -> names.add(node.name()));
    return "Topology" + names;
  }
}
