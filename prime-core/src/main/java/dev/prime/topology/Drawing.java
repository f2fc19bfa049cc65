package dev.prime.topology;

import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.Map;

/**
 * Lays a {@link Topology} out as drawn nodes and edges, then writes them as Mermaid or DOT.
 *
 * <p>Links are not drawn as nodes: a link is the edge from its first chain's exit to its second
 * chain's entry. A template, a collector and every source node is drawn once and is its own entry
 * and exit. Entries and exits of nested links are found by walking, not recursion, so a chain of
 * any length draws without deep stacks. Node ids ({@code n1}, {@code n2}, ...) follow declaration
 * order; edges are listed node by node in that order.
 */
final class Drawing {
  private final Topology topology;
  private final Map<String, String> ids = new HashMap<>();
  private final List<TopologyNode> drawn = new ArrayList<>();
  private final List<Edge> edges = new ArrayList<>();

  private record Edge(String from, String to, String label) {}

  Drawing(Topology topology) {
    this.topology = topology;
    for (TopologyNode node : topology.nodes()) {
      if (!(node instanceof TopologyNode.Link)) {
        ids.put(node.name(), "n" + (drawn.size() + 1));
        drawn.add(node);
      }
    }
    for (TopologyNode node : topology.nodes()) {
      addEdges(node);
    }
  }

  private void addEdges(TopologyNode node) {
    if (node instanceof TopologyNode.Link link) {
      edges.add(new Edge(exit(link.first()), entry(link.second()), null));
    } else if (node instanceof TopologyNode.SourceLink link) {
      edges.add(new Edge(ids.get(link.source()), entry(link.chain()), null));
      edges.add(new Edge(exit(link.chain()), ids.get(link.name()), null));
    } else {
      for (TopologyNode.Part part : node.parts()) {
        if (part.flow() == TopologyNode.Flow.READS) {
          edges.add(new Edge(exit(part.node()), ids.get(node.name()), null));
        } else {
          edges.add(new Edge(ids.get(node.name()), entry(part.node()), part.role()));
        }
      }
    }
  }

  private String entry(String name) {
    TopologyNode node = topology.node(name).orElseThrow();
    while (node instanceof TopologyNode.Link link) {
      node = topology.node(link.first()).orElseThrow();
    }
    return ids.get(node.name());
  }

  private String exit(String name) {
    TopologyNode node = topology.node(name).orElseThrow();
    while (node instanceof TopologyNode.Link link) {
      node = topology.node(link.second()).orElseThrow();
    }
    return ids.get(node.name());
  }

  private String label(TopologyNode node) {
    if (node instanceof TopologyNode.ReaderNode reader) {
      return "reader " + reader.number();
    }
    return topology.pseudoname(node.name()).map(p -> p + " (" + node.name() + ")").orElse(node.name());
  }

  private boolean elsewhere(TopologyNode node) {
    return topology.hostedElsewhere().contains(node.name());
  }

  // ---------------------------------------------------------------- Mermaid

  String mermaid() {
    StringBuilder out = new StringBuilder("flowchart LR\n");
    for (TopologyNode node : drawn) {
      String[] shape = mermaidShape(node);
      out.append("  ")
          .append(ids.get(node.name()))
          .append(shape[0])
          .append('"')
          .append(mermaidText(label(node)))
          .append('"')
          .append(shape[1])
          .append('\n');
    }
    for (Edge edge : edges) {
      out.append("  ").append(edge.from());
      if (edge.label() == null) {
        out.append(" --> ");
      } else {
        out.append(" -.->|").append(mermaidText(edge.label())).append("| ");
      }
      out.append(edge.to()).append('\n');
    }
    List<String> remote = new ArrayList<>();
    for (TopologyNode node : drawn) {
      if (elsewhere(node)) {
        remote.add(ids.get(node.name()));
      }
    }
    if (!remote.isEmpty()) {
      out.append("  classDef elsewhere stroke-dasharray: 5 5\n");
      out.append("  class ").append(String.join(",", remote)).append(" elsewhere\n");
    }
    return out.toString();
  }

  private static String[] mermaidShape(TopologyNode node) {
    if (node instanceof TopologyNode.BlockChain) {
      return new String[] {"[", "]"};
    } else if (node instanceof TopologyNode.ForeignChain) {
      return new String[] {"[/", "/]"};
    } else if (node instanceof TopologyNode.EventSource
        || node instanceof TopologyNode.Timer) {
      return new String[] {"([", "])"};
    } else if (node instanceof TopologyNode.ForeignSource) {
      return new String[] {"[\\", "\\]"};
    } else if (node instanceof TopologyNode.SourceLink
        || node instanceof TopologyNode.Filter
        || node instanceof TopologyNode.FlatMap
        || node instanceof TopologyNode.Combinator) {
      return new String[] {"[(", ")]"};
    } else if (node instanceof TopologyNode.Listener) {
      return new String[] {">", "]"};
    } else if (node instanceof TopologyNode.ReaderNode) {
      return new String[] {"((", "))"};
    } else if (node instanceof TopologyNode.GenericServiceNode) {
      return new String[] {"[[", "]]"};
    }
    return new String[] {"{{", "}}"}; // templates and collectors
  }

  /** Text inside a quoted Mermaid label: entity codes for what Mermaid or HTML would read. */
  static String mermaidText(String text) {
    StringBuilder out = new StringBuilder(text.length());
    for (int i = 0; i < text.length(); i++) {
      char c = text.charAt(i);
      switch (c) {
        case '#' -> out.append("#35;");
        case '"' -> out.append("#quot;");
        case '<' -> out.append("#lt;");
        case '&' -> out.append("#amp;");
        case '`' -> out.append("#96;");
        default -> {
          if (Character.isISOControl(c)) {
            out.append("#").append((int) c).append(';');
          } else {
            out.append(c);
          }
        }
      }
    }
    return out.toString();
  }

  // ---------------------------------------------------------------- DOT

  String dot() {
    StringBuilder out = new StringBuilder("digraph prime {\n  rankdir=LR;\n");
    for (TopologyNode node : drawn) {
      out.append("  ")
          .append(ids.get(node.name()))
          .append(" [label=")
          .append(dotString(label(node)))
          .append(", shape=")
          .append(dotShape(node));
      if (elsewhere(node)) {
        out.append(", style=dashed");
      }
      out.append("];\n");
    }
    for (Edge edge : edges) {
      out.append("  ").append(edge.from()).append(" -> ").append(edge.to());
      if (edge.label() != null) {
        out.append(" [style=dashed, label=").append(dotString(edge.label())).append(']');
      }
      out.append(";\n");
    }
    return out.append("}\n").toString();
  }

  private static String dotShape(TopologyNode node) {
    if (node instanceof TopologyNode.BlockChain) {
      return "box";
    } else if (node instanceof TopologyNode.ForeignChain) {
      return "parallelogram";
    } else if (node instanceof TopologyNode.EventSource
        || node instanceof TopologyNode.Timer) {
      return "invhouse";
    } else if (node instanceof TopologyNode.ForeignSource) {
      return "invtrapezium";
    } else if (node instanceof TopologyNode.SourceLink
        || node instanceof TopologyNode.Filter
        || node instanceof TopologyNode.FlatMap
        || node instanceof TopologyNode.Combinator) {
      return "cylinder";
    } else if (node instanceof TopologyNode.Listener) {
      return "cds";
    } else if (node instanceof TopologyNode.ReaderNode) {
      return "circle";
    } else if (node instanceof TopologyNode.GenericServiceNode) {
      return "component";
    }
    return "hexagon";
  }

  /** A DOT quoted string: backslashes and quotes escaped, control characters as escapes. */
  static String dotString(String text) {
    StringBuilder out = new StringBuilder(text.length() + 2).append('"');
    for (int i = 0; i < text.length(); i++) {
      char c = text.charAt(i);
      if (c == '"' || c == '\\') {
        out.append('\\').append(c);
      } else if (c == '\n') {
        out.append("\\n");
      } else if (Character.isISOControl(c)) {
        out.append(' ');
      } else {
        out.append(c);
      }
    }
    return out.append('"').toString();
  }
}
