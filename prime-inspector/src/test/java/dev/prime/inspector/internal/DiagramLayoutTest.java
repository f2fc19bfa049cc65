package dev.prime.inspector.internal;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
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

  @Test
  void theJsonIsEscapedForAPageAndAnEventLine() {
    Json json = new Json().beginObject().name("name").value("a</script>\n\"b\"&\u2028").endObject();
    assertEquals("{\"name\":\"a\\u003c/script\\u003e\\n\\\"b\\\"\\u0026\\u2028\"}", json.toString());
    assertEquals("[1,2.5,null,true]",
        new Json().beginArray().value(1.0).value(2.5).value(Double.NaN).value(true).endArray().toString());
  }
}
