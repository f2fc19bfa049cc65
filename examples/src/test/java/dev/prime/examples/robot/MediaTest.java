package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import dev.prime.optimus.OptimusCore;
import dev.prime.test.PrimeTest;
import java.util.Set;
import org.junit.jupiter.api.Test;

class MediaTest {

  @Test
  void everyMediaCreatesANewCoreWithTheGivenConfig() {
    for (Media media : Media.values()) {
      try (PrimeCore core = media.create(CoreConfig.builder().name("media-test").build())) {
        assertEquals("media-test", core.name());
        assertFalse(core.isStarted());
        assertEquals(media, Media.byName(media.cliName()));
      }
    }
  }

  @Test
  void libertyIsLibertyCore() {
    try (PrimeCore core = Media.byName("liberty").create(CoreConfig.defaults())) {
      assertInstanceOf(LibertyCore.class, core);
    }
  }

  @Test
  void optimusIsAnOptimusCore() {
    try (PrimeCore core = Media.byName("optimus").create(CoreConfig.defaults())) {
      assertInstanceOf(OptimusCore.class, core);
    }
  }

  /** The names a --remote option and a RobotWorker's --hosts choose from, the same on every media. */
  @PrimeTest(setup = RobotCores.class)
  void everyMediaHostsTheRobotsServices(PrimeCore core) {
    RobotController.wire(
        core,
        new WheelEncoders(RobotSpec.SMALL_INDOOR),
        RobotSpec.SMALL_INDOOR,
        new Goal(1, 1),
        Mission.DT);
    core.start();

    assertEquals(Set.copyOf(RobotController.SERVICES), core.serviceNames());
  }

  @Test
  void unknownNameIsRejected() {
    assertThrows(IllegalArgumentException.class, () -> Media.byName("carrier-pigeon"));
  }
}
