package dev.prime.topology;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.ArrayList;
import java.util.List;
import java.util.Set;
import org.junit.jupiter.api.Test;

/** The Mermaid and DOT drawings of a topology, checked against golden text. */
class TopologyExportTest {

  /**
   * A source feeding a linked chain, an if/else fed by a sync collector, a filter with a listener
   * and a reader of the linked chain's output.
   */
  private static List<TopologyNode> smallDiagram() {
    return List.of(
        new TopologyNode.EventSource("sensor"),
        new TopologyNode.BlockChain("scale"),
        new TopologyNode.BlockChain("label"),
        new TopologyNode.Link("scale>label", "scale", "label"),
        new TopologyNode.SourceLink("sensor>scale>label", "sensor", "scale>label"),
        new TopologyNode.BlockChain("a"),
        new TopologyNode.BlockChain("b"),
        new TopologyNode.IfElse("if(a|b)", "a", "b"),
        new TopologyNode.Filter("filter(sensor)", "sensor"),
        new TopologyNode.Listener("listen(filter(sensor))", "filter(sensor)"),
        new TopologyNode.ReaderNode("sensor>scale>label", 1),
        new TopologyNode.SyncCollector("collect(sensor)", "sensor"),
        new TopologyNode.Link("collect(sensor)>if(a|b)", "collect(sensor)", "if(a|b)"));
  }

  @Test
  void mermaidOfASmallDiagram() {
    assertEquals(
        """
        flowchart LR
          n1(["sensor"])
          n2["scale"]
          n3["label"]
          n4[("sensor>scale>label")]
          n5["a"]
          n6["b"]
          n7{{"if(a|b)"}}
          n8[("filter(sensor)")]
          n9>"listen(filter(sensor))"]
          n10(("reader 1"))
          n11{{"collect(sensor)"}}
          n2 --> n3
          n1 --> n2
          n3 --> n4
          n7 -.->|then| n5
          n7 -.->|else| n6
          n1 --> n8
          n8 --> n9
          n4 --> n10
          n1 --> n11
          n11 --> n7
        """,
        Topology.of(smallDiagram(), Set.of()).toMermaid());
  }

  @Test
  void dotOfASmallDiagram() {
    assertEquals(
        """
        digraph prime {
          rankdir=LR;
          n1 [label="sensor", shape=invhouse];
          n2 [label="scale", shape=box];
          n3 [label="label", shape=box];
          n4 [label="sensor>scale>label", shape=cylinder];
          n5 [label="a", shape=box];
          n6 [label="b", shape=box];
          n7 [label="if(a|b)", shape=hexagon];
          n8 [label="filter(sensor)", shape=cylinder];
          n9 [label="listen(filter(sensor))", shape=cds];
          n10 [label="reader 1", shape=circle];
          n11 [label="collect(sensor)", shape=hexagon];
          n2 -> n3;
          n1 -> n2;
          n3 -> n4;
          n7 -> n5 [style=dashed, label="then"];
          n7 -> n6 [style=dashed, label="else"];
          n1 -> n8;
          n8 -> n9;
          n4 -> n10;
          n1 -> n11;
          n11 -> n7;
        }
        """,
        Topology.of(smallDiagram(), Set.of()).toDot());
  }

  @Test
  void servicesAreTheChainsOfBlocksTemplatesAndSourceServicesInDeclarationOrder() {
    Topology topology = Topology.of(smallDiagram(), Set.of());
    assertEquals(
        List.of(
            "scale",
            "label",
            "a",
            "b",
            "if(a|b)",
            "filter(sensor)",
            "listen(filter(sensor))",
            "collect(sensor)"),
        List.copyOf(topology.services()));
    assertTrue(topology.isHostedHere("scale"));
  }

  @Test
  void servicesHostedElsewhereAreDrawnDashed() {
    Topology topology = Topology.of(smallDiagram(), Set.of("label", "a"));
    assertEquals(Set.of("a", "label"), topology.hostedElsewhere());
    String mermaid = topology.toMermaid();
    assertTrue(
        mermaid.endsWith(
            "  classDef elsewhere stroke-dasharray: 5 5\n  class n3,n5 elsewhere\n"),
        mermaid);
    assertTrue(
        topology.toDot().contains("  n3 [label=\"label\", shape=box, style=dashed];\n"),
        topology.toDot());
  }

  @Test
  void namesAreEscaped() {
    String name = "say\"hi\"#<b>&`x\\y";
    Topology topology = Topology.of(List.of(new TopologyNode.BlockChain(name)), Set.of());
    assertEquals(
        "flowchart LR\n  n1[\"say#quot;hi#quot;#35;#lt;b>#amp;#96;x\\y\"]\n",
        topology.toMermaid());
    assertEquals(
        "digraph prime {\n  rankdir=LR;\n  n1 [label=\"say\\\"hi\\\"#<b>&`x\\\\y\", shape=box];\n}\n",
        topology.toDot());
  }

  @Test
  void everyTemplateAndForeignPartIsDrawn() {
    Topology topology =
        Topology.of(
            List.of(
                new TopologyNode.BlockChain("a"),
                new TopologyNode.ForeignChain("hosted(x)", "other", "x"),
                new TopologyNode.Union("union(a|hosted(x))", List.of("a", "hosted(x)")),
                new TopologyNode.BlockChain("c"),
                new TopologyNode.ForEach("forEach(c)", "c"),
                new TopologyNode.BlockChain("d"),
                new TopologyNode.Fork("fork(d)", "d"),
                new TopologyNode.BlockChain("e"),
                new TopologyNode.Guard("guard(e)", "e"),
                new TopologyNode.BlockChain("f"),
                new TopologyNode.IsolatedUser("f@1", "f"),
                new TopologyNode.IsolatedUser("f@2", "f"),
                new TopologyNode.ForeignSource("from(other:s)", "other", "s"),
                new TopologyNode.AsyncCollector("collectAll(from(other:s))", "from(other:s)"),
                new TopologyNode.BlockChain("g"),
                new TopologyNode.Repeater("repeat(g)", "g", "collectAll(from(other:s))"),
                new TopologyNode.FlatMap("flatMap(from(other:s))", "from(other:s)")),
            Set.of());
    assertEquals(
        """
        flowchart LR
          n1["a"]
          n2[/"hosted(x)"/]
          n3{{"union(a|hosted(x))"}}
          n4["c"]
          n5{{"forEach(c)"}}
          n6["d"]
          n7{{"fork(d)"}}
          n8["e"]
          n9{{"guard(e)"}}
          n10["f"]
          n11{{"f@1"}}
          n12{{"f@2"}}
          n13[\\"from(other:s)"\\]
          n14{{"collectAll(from(other:s))"}}
          n15["g"]
          n16{{"repeat(g)"}}
          n17[("flatMap(from(other:s))")]
          n3 -.->|1| n1
          n3 -.->|2| n2
          n5 -.->|body| n4
          n7 -.->|chain| n6
          n9 -.->|chain| n8
          n11 -.->|shared| n10
          n12 -.->|shared| n10
          n13 --> n14
          n16 -.->|inner| n15
          n16 -.->|collects| n14
          n13 --> n17
        """,
        topology.toMermaid());
  }

  @Test
  void aChainOfManyLinksDrawsWithoutDeepRecursion() {
    int links = 100_000;
    List<TopologyNode> nodes = new ArrayList<>();
    nodes.add(new TopologyNode.BlockChain("c0"));
    String chain = "c0";
    for (int i = 1; i <= links; i++) {
      nodes.add(new TopologyNode.BlockChain("c" + i));
      String linked = "l" + i;
      nodes.add(new TopologyNode.Link(linked, chain, "c" + i));
      chain = linked;
    }
    String mermaid = Topology.of(nodes, Set.of()).toMermaid();
    assertTrue(mermaid.endsWith("  n100000 --> n100001\n"), mermaid.substring(mermaid.length() - 40));
  }

  @Test
  void badTopologiesAreRefusedWithTheReason() {
    IllegalArgumentException forward =
        assertThrows(
            IllegalArgumentException.class,
            () ->
                Topology.of(
                    List.of(new TopologyNode.Guard("guard(a)", "a"), new TopologyNode.BlockChain("a")),
                    Set.of()));
    assertTrue(forward.getMessage().contains("not declared before"), forward.getMessage());
    IllegalArgumentException twice =
        assertThrows(
            IllegalArgumentException.class,
            () ->
                Topology.of(
                    List.of(new TopologyNode.BlockChain("a"), new TopologyNode.EventSource("a")),
                    Set.of()));
    assertTrue(twice.getMessage().contains("two nodes are named 'a'"), twice.getMessage());
    IllegalArgumentException notAService =
        assertThrows(
            IllegalArgumentException.class,
            () -> Topology.of(List.of(new TopologyNode.EventSource("s")), Set.of("s")));
    assertTrue(notAService.getMessage().contains("not a service"), notAService.getMessage());
  }
}
