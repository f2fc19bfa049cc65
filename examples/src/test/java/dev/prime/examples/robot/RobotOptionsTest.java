package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.Set;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

class RobotOptionsTest {

  @Test
  void noArgumentsGiveTheDefaults() {
    assertEquals(RobotOptions.DEFAULTS, RobotOptions.parse());
    assertEquals(Media.LIBERTY, RobotOptions.DEFAULTS.media());
  }

  @Test
  void parsesEveryOptionInBothForms() {
    RobotOptions options =
        RobotOptions.parse(
            "--media", "LIBERTY", "--goal=1.5,-0.5", "--steps", "40", "--trace-every=7");

    assertEquals(
        new RobotOptions(
            Media.LIBERTY,
            new Goal(1.5, -0.5),
            40,
            7,
            false,
            null,
            List.of(),
            "robot",
            null,
            null,
            Set.of("--media", "--goal", "--steps", "--trace-every")),
        options);
  }

  @Test
  void optimusTakesARedisUrlAndServicesLeftToAWorker() {
    RobotOptions options =
        RobotOptions.parse(
            "--media", "optimus", "--redis=redis://localhost:6379", "--remote", "planner,pid",
            "--name", "robot-2");

    assertEquals(Media.OPTIMUS, options.media());
    assertEquals("redis://localhost:6379", options.redisUrl());
    assertEquals(List.of("planner", "pid"), options.remote());
    assertEquals("robot-2", options.coreConfig().name());
    assertEquals(
        List.of("odometry", "guard(planner>pid)", "collect(encoders>odometry)"),
        options.hosted());
    assertNull(RobotOptions.parse("--media", "optimus").hosted(), "no --remote: hosts all");
  }

  @Test
  void redisAndRemoteOptionsSayWhatIsWrong() {
    assertEquals(
        "--redis only applies to --media optimus",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--redis", "redis://h:1"))
            .getMessage());
    assertTrue(
        assertThrows(
                UsageException.class,
                () -> RobotOptions.parse("--media", "optimus", "--redis", "http://h:1"))
            .getMessage()
            .startsWith("--redis: "));
    assertEquals(
        "--remote needs --redis URL (and --media optimus): the worker that runs those services"
            + " must reach the same Redis",
        assertThrows(
                UsageException.class,
                () -> RobotOptions.parse("--media", "optimus", "--remote", "planner"))
            .getMessage());
    assertEquals(
        "--remote: unknown service 'brakes'; the robot's services: odometry, planner, pid,"
            + " guard(planner>pid), collect(encoders>odometry)",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--remote", "planner,brakes"))
            .getMessage());
  }

  @Test
  void helpWins() {
    assertTrue(RobotOptions.parse("--steps", "3", "--help").help());
  }

  @Test
  void unknownMediaNamesTheKnownOnes() {
    UsageException e =
        assertThrows(UsageException.class, () -> RobotOptions.parse("--media", "warp"));
    assertEquals("unknown media 'warp'; known media: liberty, radiant, optimus", e.getMessage());
  }

  @Test
  void badArgumentsSayWhatIsWrong() {
    assertEquals(
        "unknown argument '--fast'",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--fast")).getMessage());
    assertEquals(
        "--media needs a value",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--media")).getMessage());
    assertEquals(
        "--goal wants two numbers X,Y in metres, like 2,1; got '3'",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--goal", "3")).getMessage());
    assertEquals(
        "--goal wants two finite numbers X,Y in metres, like 2,1; got '1,NaN'",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--goal", "1,NaN"))
            .getMessage());
    assertEquals(
        "--steps wants a whole number of at least 1; got '0'",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--steps", "0")).getMessage());
  }

  @Test
  void recordTurnsRecordingOnAndReplayWantsAnExistingFile(@TempDir Path dir) throws Exception {
    RobotOptions record = RobotOptions.parse("--record", dir.resolve("run.mcap").toString(), "--steps", "40");
    assertEquals(dir.resolve("run.mcap"), record.record());
    assertEquals(41, record.coreConfig().recording().capacity());
    assertNull(RobotOptions.parse().coreConfig().recording(), "off by default");

    Path file = Files.writeString(dir.resolve("run.mcap"), "x");
    assertEquals(file, RobotOptions.parse("--replay=" + file).replay());
    assertEquals(
        "--replay: no file 'nothing.mcap'; give an MCAP file written with --record",
        assertThrows(UsageException.class, () -> RobotOptions.parse("--replay", "nothing.mcap"))
            .getMessage());
    assertTrue(
        assertThrows(
                UsageException.class,
                () -> RobotOptions.parse("--record", dir.resolve("no/such/dir.mcap").toString()))
            .getMessage()
            .startsWith("--record wants a file in an existing directory"));
    assertTrue(
        assertThrows(
                UsageException.class,
                () -> RobotOptions.parse("--record", "a.mcap", "--replay", file.toString()))
            .getMessage()
            .startsWith("--record and --replay cannot be combined"));
  }
}
