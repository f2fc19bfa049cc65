package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.topology.Topology;
import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.Set;
import org.junit.jupiter.api.Test;

/** The robot's diagram, drawn from its code: the same on every media, and the README shows it. */
class RobotTopologyTest {

  /** The robot declared on a new core of {@code media}, and that core's service names. */
  private record Declared(Topology topology, Set<String> services) {}

  private static Declared declareOn(Media media) {
    CoreConfig config = CoreConfig.builder().name("robot-topology-" + media.cliName()).build();
    try (PrimeCore core = media.create(config)) {
      RobotController.wire(
          core,
          new WheelEncoders(RobotSpec.SMALL_INDOOR),
          RobotSpec.SMALL_INDOOR,
          new Goal(1, 1),
          Mission.DT);
      return new Declared(core.topology(), core.serviceNames());
    }
  }

  @Test
  void everyMediaHasTheSameTopologyDrawingsAndServices() {
    Declared liberty = declareOn(Media.LIBERTY);
    assertEquals(List.copyOf(RobotController.SERVICES), List.copyOf(liberty.services()));
    for (Media media : List.of(Media.RADIANT, Media.OPTIMUS)) {
      Declared other = declareOn(media);
      assertEquals(liberty.topology(), other.topology(), media.cliName());
      assertEquals(liberty.topology().toMermaid(), other.topology().toMermaid(), media.cliName());
      assertEquals(liberty.topology().toDot(), other.topology().toDot(), media.cliName());
      assertEquals(liberty.services(), other.services(), media.cliName());
    }
  }

  /** The README's robot diagram is what the code draws; the message has the block to paste. */
  @Test
  void readmeShowsTheRobotsDiagramAsTheCodeDrawsIt() throws IOException {
    String block = "```mermaid\n" + declareOn(Media.LIBERTY).topology().toMermaid() + "```\n";
    String readme = Files.readString(Path.of("../README.md"));
    assertTrue(
        readme.contains(block),
        "README.md must show the robot's diagram as the code draws it; replace its mermaid block"
            + " with:\n"
            + block);
  }
}
