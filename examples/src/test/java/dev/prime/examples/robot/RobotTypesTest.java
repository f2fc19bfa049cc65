package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.optimus.KryoCodec;
import java.util.List;
import org.junit.jupiter.api.Test;

class RobotTypesTest {

  @Test
  void codecAllowsTheRobotsTypesUnderIdsThatDoNotDependOnTheOrder() {
    KryoCodec codec = RobotTypes.codec();

    // registrations are "id class-name", the built-in types first, then the declared ones by name
    List<String> registered = codec.registeredTypes();
    int end = registered.size() - 1; // the last line is the rule for records and enums sent
    List<String> application =
        registered.subList(end - RobotTypes.ALL.size(), end).stream()
            .map(entry -> entry.substring(entry.indexOf(' ') + 1))
            .toList();
    assertEquals(RobotTypes.ALL.stream().map(Class::getName).sorted().toList(), application);
    assertEquals(codec.fingerprint(), RobotTypes.codec().fingerprint(), "same in every process");

    KryoCodec.Builder reversed = KryoCodec.builder();
    for (int i = RobotTypes.ALL.size() - 1; i >= 0; i--) {
      reversed.allow(RobotTypes.ALL.get(i));
    }
    assertEquals(codec.fingerprint(), reversed.build().fingerprint(), "in any order");
  }

  @Test
  void aDriveCommandCrossesTheCodecWithEverythingInsideIt() {
    KryoCodec codec = RobotTypes.codec();
    DriveCommand command =
        new DriveCommand(
            new Estimate(7, new Pose(1.5, -0.25, 0.3), new WheelSpeeds(0.1, 0.2)),
            new WheelSpeeds(0.3, 0.4),
            1.25,
            -2.5,
            false);

    assertEquals(command, codec.decode(codec.encode(command)));
  }
}
