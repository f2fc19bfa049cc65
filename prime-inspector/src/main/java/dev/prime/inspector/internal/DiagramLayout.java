package dev.prime.inspector.internal;

import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Comparator;
import java.util.Deque;
import java.util.HashMap;
import java.util.List;
import java.util.Map;

/**
 * Lays a {@link Topology} out left to right in layers, for the page to draw as SVG.
 *
 * <p>What is drawn follows the core's own Mermaid and DOT drawings: every node but a link is a
 * box; a link is the edge from its first chain's exit to its second chain's entry; a chain linked
 * to a source gets an edge from the source into the chain and one from the chain out to the
 * source of its outputs; a node that reads a part gets an edge from it, and a template an edge
 * (with the part's role) to each chain it runs.
 *
 * <p>The layout is the usual layered one, kept small: (1) each box's layer is the longest path to
 * it, taken in a topological order of the edges (boxes on a cycle, which the model does not
 * make, are placed in declaration order, the edges closing the cycle ignored); (2) the boxes of
 * each layer are ordered by the mean position of their neighbours in the layer before, then in
 * the layer after, a few sweeps; (3) layers become columns as wide as their widest box, boxes
 * rows centred in the tallest column. Everything is linear in the nodes and edges, but for the
 * sorting of each layer, and walks rather than recurses, so any size lays out.
 */
public final class DiagramLayout {
  /** Height of a box: its label and a line of figures. */
  static final int BOX_HEIGHT = 52;
  private static final int ROW_GAP = 34;
  private static final int COLUMN_GAP = 60;
  private static final int MARGIN = 20;
  private static final int MIN_WIDTH = 176; // room for a line of figures: "101.5/s · 6.3 µs · 0 err"
  private static final int MAX_WIDTH = 280;
  private static final int SWEEPS = 4;

  /**
   * One box of the diagram.
   *
   * @param id a short id ({@code n1}, {@code n2}, ... in declaration order)
   * @param name the node's name in the topology
   * @param label what the box says: the pseudoname and the name, or the name
   * @param kind the node's kind: the simple name of its {@link TopologyNode} record
   * @param service whether the node is a service
   * @param elsewhere whether another process hosts it
   * @param layer its column, from 0
   * @param x left edge
   * @param y top edge
   * @param width width
   * @param height height
   */
  public record Box(
      String id,
      String name,
      String label,
      String kind,
      boolean service,
      boolean elsewhere,
      int layer,
      int x,
      int y,
      int width,
      int height) {}

  /**
   * One arrow.
   *
   * @param from the id of the box it leaves
   * @param to the id of the box it enters
   * @param role {@code null} for values flowing; otherwise the part's role for a template
   *     running a chain ({@code then}, {@code body}, ...), drawn dashed
   */
  public record Arrow(String from, String to, String role) {}

  private final List<Box> boxes;
  private final List<Arrow> arrows;
  private final int width;
  private final int height;

  private DiagramLayout(List<Box> boxes, List<Arrow> arrows, int width, int height) {
    this.boxes = List.copyOf(boxes);
    this.arrows = List.copyOf(arrows);
    this.width = width;
    this.height = height;
  }

  /** {@return the boxes, in declaration order} */
  public List<Box> boxes() {
    return boxes;
  }

  /** {@return the arrows, node by node in declaration order} */
  public List<Arrow> arrows() {
    return arrows;
  }

  /** {@return the width of the whole drawing} */
  public int width() {
    return width;
  }

  /** {@return the height of the whole drawing} */
  public int height() {
    return height;
  }

  /**
   * Lays a topology out.
   *
   * @param topology the diagram
   * @return its layout
   */
  public static DiagramLayout of(Topology topology) {
    List<TopologyNode> drawn = new ArrayList<>();
    Map<String, Integer> index = new HashMap<>();
    for (TopologyNode node : topology.nodes()) {
      if (!(node instanceof TopologyNode.Link)) {
        index.put(node.name(), drawn.size());
        drawn.add(node);
      }
    }
    int n = drawn.size();
    // The box a value enters and the one it leaves each node by: a link's are its first chain's
    // entry and its second chain's exit, found once per node in declaration order (a link's
    // chains come before it), so a deeply nested link costs no walk down it at each use.
    Map<String, Integer> entry = new HashMap<>();
    Map<String, Integer> exit = new HashMap<>();
    for (TopologyNode node : topology.nodes()) {
      if (node instanceof TopologyNode.Link link) {
        entry.put(link.name(), entry.get(link.first()));
        exit.put(link.name(), exit.get(link.second()));
      } else {
        entry.put(node.name(), index.get(node.name()));
        exit.put(node.name(), index.get(node.name()));
      }
    }
    List<int[]> edges = new ArrayList<>();
    List<String> roles = new ArrayList<>();
    for (TopologyNode node : topology.nodes()) {
      if (node instanceof TopologyNode.Link link) {
        addEdge(edges, roles, exit.get(link.first()), entry.get(link.second()), null);
      } else if (node instanceof TopologyNode.SourceLink link) {
        addEdge(edges, roles, index.get(link.source()), entry.get(link.chain()), null);
        addEdge(edges, roles, exit.get(link.chain()), index.get(link.name()), null);
      } else {
        for (TopologyNode.Part part : node.parts()) {
          if (part.flow() == TopologyNode.Flow.READS) {
            addEdge(edges, roles, exit.get(part.node()), index.get(node.name()), null);
          } else {
            addEdge(edges, roles, index.get(node.name()), entry.get(part.node()), part.role());
          }
        }
      }
    }

    int[] layer = layers(n, edges);
    int layers = 0;
    for (int l : layer) {
      layers = Math.max(layers, l + 1);
    }
    List<List<Integer>> columns = new ArrayList<>();
    for (int l = 0; l < layers; l++) {
      columns.add(new ArrayList<>());
    }
    for (int i = 0; i < n; i++) {
      columns.get(layer[i]).add(i);
    }
    order(columns, layer, edges, n);

    String[] labels = new String[n];
    int[] widths = new int[n];
    for (int i = 0; i < n; i++) {
      TopologyNode node = drawn.get(i);
      labels[i] = label(topology, node);
      widths[i] = boxWidth(labels[i]);
    }
    int[] xs = new int[n];
    int[] ys = new int[n];
    int tallest = 0;
    for (List<Integer> column : columns) {
      tallest = Math.max(tallest, column.size());
    }
    int fullHeight = tallest * BOX_HEIGHT + Math.max(0, tallest - 1) * ROW_GAP;
    int x = MARGIN;
    for (List<Integer> column : columns) {
      int columnWidth = 0;
      for (int i : column) {
        columnWidth = Math.max(columnWidth, widths[i]);
      }
      int columnHeight = column.size() * BOX_HEIGHT + Math.max(0, column.size() - 1) * ROW_GAP;
      int y = MARGIN + (fullHeight - columnHeight) / 2;
      for (int i : column) {
        xs[i] = x + (columnWidth - widths[i]) / 2;
        ys[i] = y;
        y += BOX_HEIGHT + ROW_GAP;
      }
      x += columnWidth + COLUMN_GAP;
    }

    List<Box> boxes = new ArrayList<>(n);
    for (int i = 0; i < n; i++) {
      TopologyNode node = drawn.get(i);
      boxes.add(
          new Box(
              "n" + (i + 1),
              node.name(),
              labels[i],
              node.getClass().getSimpleName(),
              node.isService(),
              topology.hostedElsewhere().contains(node.name()),
              layer[i],
              xs[i],
              ys[i],
              widths[i],
              BOX_HEIGHT));
    }
    List<Arrow> arrows = new ArrayList<>(edges.size());
    for (int e = 0; e < edges.size(); e++) {
      arrows.add(new Arrow("n" + (edges.get(e)[0] + 1), "n" + (edges.get(e)[1] + 1), roles.get(e)));
    }
    int totalWidth = columns.isEmpty() ? 2 * MARGIN : x - COLUMN_GAP + MARGIN;
    return new DiagramLayout(boxes, arrows, totalWidth, fullHeight + 2 * MARGIN);
  }

  /** The layout as the page reads it. */
  void write(Json json) {
    json.name("width").value(width).name("height").value(height);
    json.name("nodes").beginArray();
    for (Box box : boxes) {
      json.beginObject()
          .name("id").value(box.id())
          .name("name").value(box.name())
          .name("label").value(box.label())
          .name("kind").value(box.kind())
          .name("service").value(box.service())
          .name("elsewhere").value(box.elsewhere())
          .name("layer").value(box.layer())
          .name("x").value(box.x())
          .name("y").value(box.y())
          .name("width").value(box.width())
          .name("height").value(box.height())
          .endObject();
    }
    json.endArray();
    json.name("edges").beginArray();
    for (Arrow arrow : arrows) {
      json.beginObject().name("from").value(arrow.from()).name("to").value(arrow.to());
      json.name("role").value(arrow.role());
      json.endObject();
    }
    json.endArray();
  }

  private static void addEdge(List<int[]> edges, List<String> roles, int from, int to, String role) {
    edges.add(new int[] {from, to});
    roles.add(role);
  }

  /** Longest-path layers over a topological order (Kahn's, ties in declaration order). */
  private static int[] layers(int n, List<int[]> edges) {
    List<List<Integer>> out = adjacency(n, edges, 0, 1);
    int[] inDegree = new int[n];
    for (int[] edge : edges) {
      inDegree[edge[1]]++;
    }
    int[] position = new int[n];
    java.util.Arrays.fill(position, -1);
    java.util.PriorityQueue<Integer> ready = new java.util.PriorityQueue<>();
    for (int i = 0; i < n; i++) {
      if (inDegree[i] == 0) {
        ready.add(i);
      }
    }
    int placed = 0;
    List<Integer> order = new ArrayList<>(n);
    while (placed < n) {
      if (ready.isEmpty()) {
        // a cycle: take the first node not yet placed, as if its remaining inputs were not there
        for (int i = 0; i < n; i++) {
          if (position[i] < 0 && inDegree[i] > 0) {
            inDegree[i] = 0;
            ready.add(i);
            break;
          }
        }
      }
      int next = ready.poll();
      position[next] = placed++;
      order.add(next);
      for (int to : out.get(next)) {
        if (position[to] < 0 && --inDegree[to] == 0) {
          ready.add(to);
        }
      }
    }
    int[] layer = new int[n];
    List<List<Integer>> in = adjacency(n, edges, 1, 0);
    for (int node : order) {
      for (int from : in.get(node)) {
        if (position[from] < position[node]) {
          layer[node] = Math.max(layer[node], layer[from] + 1);
        }
      }
    }
    return layer;
  }

  /** Barycentre sweeps: each layer sorted by its neighbours' positions in the layer swept from. */
  private static void order(List<List<Integer>> columns, int[] layer, List<int[]> edges, int n) {
    List<List<Integer>> in = adjacency(n, edges, 1, 0);
    List<List<Integer>> out = adjacency(n, edges, 0, 1);
    double[] position = new double[n];
    for (List<Integer> column : columns) {
      for (int i = 0; i < column.size(); i++) {
        position[column.get(i)] = i;
      }
    }
    for (int sweep = 0; sweep < SWEEPS; sweep++) {
      boolean forward = sweep % 2 == 0;
      Deque<List<Integer>> pending = new ArrayDeque<>(columns);
      while (!pending.isEmpty()) {
        List<Integer> column = forward ? pending.pollFirst() : pending.pollLast();
        List<List<Integer>> neighbours = forward ? in : out;
        Map<Integer, Double> key = new HashMap<>();
        for (int node : column) {
          double sum = 0;
          int count = 0;
          for (int other : neighbours.get(node)) {
            if (Math.abs(layer[other] - layer[node]) == 1) {
              sum += position[other];
              count++;
            }
          }
          key.put(node, count == 0 ? position[node] : sum / count);
        }
        column.sort(Comparator.comparingDouble(key::get));
        for (int i = 0; i < column.size(); i++) {
          position[column.get(i)] = i;
        }
      }
    }
  }

  private static List<List<Integer>> adjacency(int n, List<int[]> edges, int from, int to) {
    List<List<Integer>> lists = new ArrayList<>(n);
    for (int i = 0; i < n; i++) {
      lists.add(new ArrayList<>());
    }
    for (int[] edge : edges) {
      lists.get(edge[from]).add(edge[to]);
    }
    return lists;
  }

  private static String label(Topology topology, TopologyNode node) {
    if (node instanceof TopologyNode.ReaderNode reader) {
      return "reader " + reader.number();
    }
    return topology
        .pseudoname(node.name())
        .map(pseudoname -> pseudoname + " (" + node.name() + ")")
        .orElse(node.name());
  }

  /** About 7 pixels a character at the page's 12 px font, within bounds (longer labels are cut). */
  private static int boxWidth(String label) {
    return Math.max(MIN_WIDTH, Math.min(MAX_WIDTH, label.length() * 7 + 28));
  }
}
