package dev.prime.inspector.internal;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTimeoutPreemptively;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
import java.time.Duration;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.Map;
import java.util.Set;
import org.junit.jupiter.api.Test;

class DiagramLayoutTest {
  /** The robot example's topology, as its core records it. */
  private static Topology robot() {
    return Topology.of(
        List.of(
            new TopologyNode.EventSource("encoders"),
            new TopologyNode.BlockChain("odometry"),
            new TopologyNode.SourceLink("encoders>odometry", "encoders", "odometry"),
            new TopologyNode.BlockChain("planner"),
            new TopologyNode.BlockChain("pid"),
            new TopologyNode.Link("planner>pid", "planner", "pid"),
            new TopologyNode.Guard("guard(planner>pid)", "planner>pid"),
            new TopologyNode.SyncCollector("collect(encoders>odometry)", "encoders>odometry"),
            new TopologyNode.Link(
                "collect(encoders>odometry)>guard(planner>pid)",
                "collect(encoders>odometry)",
                "guard(planner>pid)"),
            new TopologyNode.ReaderNode("encoders>odometry", 1)),
        Set.of("planner"),
        Map.of("odometry", "Wheel odometry"));
  }

  private static Map<String, DiagramLayout.Box> byName(DiagramLayout layout) {
    Map<String, DiagramLayout.Box> boxes = new HashMap<>();
    layout.boxes().forEach(box -> boxes.put(box.name(), box));
    return boxes;
  }

  @Test
  void everyNodeButLinksIsABoxAndLinksAreArrows() {
    DiagramLayout layout = DiagramLayout.of(robot());
    List<String> names = new ArrayList<>();
    layout.boxes().forEach(box -> names.add(box.name()));
    assertEquals(
        List.of("encoders", "odometry", "encoders>odometry", "planner", "pid", "guard(planner>pid)",
            "collect(encoders>odometry)", "encoders>odometry reader 1"),
        names);
    Map<String, DiagramLayout.Box> boxes = byName(layout);
    Set<String> arrows = new java.util.HashSet<>();
    Map<String, String> names2 = new HashMap<>();
    layout.boxes().forEach(box -> names2.put(box.id(), box.name()));
    for (DiagramLayout.Arrow arrow : layout.arrows()) {
      arrows.add(names2.get(arrow.from()) + " -> " + names2.get(arrow.to())
          + (arrow.role() == null ? "" : " [" + arrow.role() + "]"));
    }
    assertEquals(
        Set.of(
            "encoders -> odometry",
            "odometry -> encoders>odometry",
            "planner -> pid",
            "guard(planner>pid) -> planner [chain]",
            "encoders>odometry -> collect(encoders>odometry)",
            "collect(encoders>odometry) -> guard(planner>pid)",
            "encoders>odometry -> encoders>odometry reader 1"),
        arrows);
    assertEquals("Wheel odometry (odometry)", boxes.get("odometry").label());
    assertEquals("reader 1", boxes.get("encoders>odometry reader 1").label());
    assertTrue(boxes.get("planner").elsewhere());
    assertFalse(boxes.get("pid").elsewhere());
    assertEquals("Guard", boxes.get("guard(planner>pid)").kind());
  }

  @Test
  void everyArrowGoesRightAndNoBoxesOverlap() {
    DiagramLayout layout = DiagramLayout.of(robot());
    Map<String, DiagramLayout.Box> byId = new HashMap<>();
    layout.boxes().forEach(box -> byId.put(box.id(), box));
    for (DiagramLayout.Arrow arrow : layout.arrows()) {
      DiagramLayout.Box from = byId.get(arrow.from());
      DiagramLayout.Box to = byId.get(arrow.to());
      assertTrue(to.layer() > from.layer(), arrow + ": " + from + " to " + to);
      assertTrue(to.x() >= from.x() + from.width(), "drawn left to right: " + arrow);
    }
    List<DiagramLayout.Box> boxes = layout.boxes();
    for (int i = 0; i < boxes.size(); i++) {
      DiagramLayout.Box a = boxes.get(i);
      assertTrue(a.x() >= 0 && a.y() >= 0 && a.x() + a.width() <= layout.width()
          && a.y() + a.height() <= layout.height(), "inside the drawing: " + a);
      for (int j = i + 1; j < boxes.size(); j++) {
        DiagramLayout.Box b = boxes.get(j);
        boolean apart = a.x() + a.width() <= b.x() || b.x() + b.width() <= a.x()
            || a.y() + a.height() <= b.y() || b.y() + b.height() <= a.y();
        assertTrue(apart, a + " overlaps " + b);
      }
    }
  }

  @Test
  void aLongChainLaysOutWithoutDeepStacksOrQuadraticTime() {
    List<TopologyNode> nodes = new ArrayList<>();
    nodes.add(new TopologyNode.BlockChain("c0"));
    String previous = "c0";
    int n = 20_000;
    for (int i = 1; i < n; i++) {
      nodes.add(new TopologyNode.BlockChain("c" + i));
      String link = "l" + i;
      nodes.add(new TopologyNode.Link(link, previous, "c" + i));
      previous = link;
    }
    DiagramLayout layout = DiagramLayout.of(Topology.of(nodes, Set.of()));
    assertEquals(n, layout.boxes().size());
    assertEquals(n - 1, layout.arrows().size());
    assertEquals(n - 1, layout.boxes().get(n - 1).layer());
  }

  /**
   * Deeply nested links, each level of them used: a right-nested chain ({@code
   * c0.link(c1.link(c2...))}) whose every level a source is linked to (each level's exit is the
   * last chain), and a left-nested one ({@code ((c0.link(c1)).link(c2))...}) whose every level a
   * guard runs (each level's entry is the first chain). A layout that walks each level's links
   * down to its entry or exit takes steps of the square of the depth: at this depth, minutes,
   * past the test's bound; one that finds each node's entry and exit once lays them out in about
   * a second.
   */
  @Test
  void deeplyNestedLinksUsedAtEveryLevelLayOutInLinearTime() {
    int depth = 100_000;
    Duration bound = Duration.ofSeconds(60);

    List<TopologyNode> right = new ArrayList<>();
    right.add(new TopologyNode.EventSource("src"));
    right.add(new TopologyNode.BlockChain("c" + depth));
    String tail = "c" + depth;
    for (int i = depth - 1; i >= 0; i--) {
      right.add(new TopologyNode.BlockChain("c" + i));
      right.add(new TopologyNode.Link("l" + i, "c" + i, tail));
      right.add(new TopologyNode.SourceLink("s" + i, "src", "l" + i));
      tail = "l" + i;
    }
    Topology rightNested = Topology.of(right, Set.of());
    DiagramLayout rightLayout =
        assertTimeoutPreemptively(bound, () -> DiagramLayout.of(rightNested), "right-nested links");
    Map<String, String> rightNames = new HashMap<>();
    rightLayout.boxes().forEach(box -> rightNames.put(box.id(), box.name()));
    assertEquals(depth + depth * 2, rightLayout.arrows().size(), "a link's arrow, a source link's two");
    int intoOutputs = 0;
    for (DiagramLayout.Arrow arrow : rightLayout.arrows()) {
      if (rightNames.get(arrow.to()).startsWith("s")) {
        assertEquals("c" + depth, rightNames.get(arrow.from()), "each level's exit is the last chain");
        intoOutputs++;
      }
    }
    assertEquals(depth, intoOutputs);
    assertEquals(depth + 2, byName(rightLayout).get("s0").layer());

    List<TopologyNode> left = new ArrayList<>();
    left.add(new TopologyNode.BlockChain("c0"));
    String head = "c0";
    for (int i = 1; i <= depth; i++) {
      left.add(new TopologyNode.BlockChain("c" + i));
      left.add(new TopologyNode.Link("l" + i, head, "c" + i));
      left.add(new TopologyNode.Guard("g" + i, "l" + i));
      head = "l" + i;
    }
    Topology leftNested = Topology.of(left, Set.of());
    DiagramLayout leftLayout =
        assertTimeoutPreemptively(bound, () -> DiagramLayout.of(leftNested), "left-nested links");
    Map<String, String> leftNames = new HashMap<>();
    leftLayout.boxes().forEach(box -> leftNames.put(box.id(), box.name()));
    int runs = 0;
    for (DiagramLayout.Arrow arrow : leftLayout.arrows()) {
      if (arrow.role() != null) {
        assertEquals("c0", leftNames.get(arrow.to()), "each level's entry is the first chain");
        runs++;
      }
    }
    assertEquals(depth, runs);
  }

  @Test
  void theJsonIsEscapedForAPageAndAnEventLine() {
    Json json = new Json().beginObject().name("name").value("a</script>\n\"b\"&\u2028").endObject();
    assertEquals("{\"name\":\"a\\u003c/script\\u003e\\n\\\"b\\\"\\u0026\\u2028\"}", json.toString());
    assertEquals("[1,2.5,null,true]",
        new Json().beginArray().value(1.0).value(2.5).value(Double.NaN).value(true).endArray().toString());
  }
}
