package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.inspector.HeadlessChromium;
import dev.prime.inspector.PrimeInspector;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.ServerSocket;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.time.Duration;
import java.util.HashSet;
import java.util.List;
import java.util.Set;
import org.junit.jupiter.api.Test;

/**
 * The robot on its live page, read in a headless Chromium (skipped, with the reason, where none
 * is installed). With {@code -Dprime.inspector.screenshot=FILE} the test also writes a screenshot
 * of the page (the README's is made so).
 */
class WatchedRobotTest {
  private static final Duration PATIENCE = Duration.ofSeconds(30);

  private static String attribute(String name, String attribute) {
    return "(() => { const g = document.querySelector('#diagram g.node[data-name=\"" + name + "\"]');"
        + " return g && g.hasAttribute('" + attribute + "') ? Number(g.getAttribute('" + attribute
        + "')) : null; })()";
  }

  @Test
  void thePageDrawsTheRobotAndFollowsItToItsGoal() throws Exception {
    HeadlessChromium.requireBinary();
    try (WatchedRobot robot =
        new WatchedRobot(Media.LIBERTY, new Goal(2, 1), new InetSocketAddress(InetAddress.getLoopbackAddress(), 0))) {
      try (HeadlessChromium chromium =
          HeadlessChromium.open(robot.uri().resolve("/#plot=odometry"), 1400, 700)) {
        Set<String> expected = new HashSet<>(RobotController.SERVICES);
        expected.add(RobotController.ENCODERS);
        JsonNode drawn =
            chromium.await(
                "[...document.querySelectorAll('#diagram g.node')].map(g => g.dataset.name)",
                names -> {
                  Set<String> seen = new HashSet<>();
                  names.forEach(n -> seen.add(n.asText()));
                  return seen.containsAll(expected);
                },
                PATIENCE, "the page should draw every service of the robot " + expected);
        assertEquals(robot.core().topology().nodes().stream().filter(n -> !(n instanceof dev.prime.topology.TopologyNode.Link)).count(),
            drawn.size(), "one box per node but links: " + drawn);

        // driving: real time is 100 steps a second
        chromium.await(attribute("odometry", "data-rate"), r -> r.isNumber() && r.asDouble() > 50,
            PATIENCE, "odometry should run at about 100/s");
        chromium.await(attribute("planner", "data-rate"), r -> r.isNumber() && r.asDouble() > 50,
            PATIENCE, "the planner should run while the robot drives");
        chromium.await(attribute("planner", "data-latencyms"), ms -> ms.isNumber() && ms.asDouble() > 0,
            PATIENCE, "the planner's processing time should be shown");
        chromium.await(
            "[...document.querySelectorAll('#plot polyline.series')].filter(p => Number(p.dataset.points) >= 2)"
                + ".map(p => p.dataset.field)",
            f -> {
              Set<String> fields = new HashSet<>();
              f.forEach(n -> fields.add(n.asText()));
              return fields.containsAll(List.of("pose.x", "pose.y", "pose.heading"));
            },
            PATIENCE, "odometry's pose should be plotted");

        // at the goal the guard stops running the planner: its rate falls to 0, odometry's not
        long deadline = System.nanoTime() + PATIENCE.toNanos();
        while (!robot.arrived()) {
          assertTrue(System.nanoTime() < deadline, "the robot did not reach its goal within " + PATIENCE);
          Thread.sleep(50); // polling the robot, bounded by the deadline
        }
        chromium.await(attribute("planner", "data-rate"), r -> r.isNumber() && r.asDouble() == 0,
            PATIENCE, "the planner's rate should fall to 0 once the robot holds at its goal");
        assertTrue(
            chromium.evaluate(attribute("odometry", "data-rate")).asDouble() > 50,
            "odometry still runs at the goal");

        String screenshot = System.getProperty("prime.inspector.screenshot");
        if (screenshot != null && !screenshot.isBlank()) {
          Thread.sleep(1500); // let the plot show the hold at the goal for the picture
          chromium.screenshot(Path.of(screenshot));
          assertTrue(Files.size(Path.of(screenshot)) > 10_000);
        }
      }
    }
  }

  @Test
  void onOptimusTheServicesAnotherProcessHostsAreDrawnDashed() throws Exception {
    HeadlessChromium.requireBinary();
    List<String> hostedHere = List.of("odometry", "collect(encoders>odometry)");
    try (PrimeCore core =
        Media.optimus(CoreConfig.builder().name("split").metrics(true).build(), null, hostedHere)) {
      RobotController.wire(
          core, new WheelEncoders(RobotSpec.SMALL_INDOOR), RobotSpec.SMALL_INDOOR, new Goal(2, 1), Mission.DT);
      core.start();
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium = HeadlessChromium.open(inspector.uri(), 1400, 700)) {
        JsonNode dashed =
            chromium.await(
                "[...document.querySelectorAll('#diagram g.node.elsewhere')].map(g => g.dataset.name)",
                names -> names.size() == 3, PATIENCE,
                "the three services another process hosts should be drawn dashed");
        Set<String> elsewhere = new HashSet<>();
        dashed.forEach(n -> elsewhere.add(n.asText()));
        assertEquals(Set.of("planner", "pid", "guard(planner>pid)"), elsewhere);
        assertEquals(core.topology().hostedElsewhere(), elsewhere);
        String header = chromium.evaluate("document.getElementById('core').textContent").asText();
        assertTrue(header.contains("core 'split' on OptimusCore"), header);
        assertTrue(header.contains("3 of 5 services hosted by other processes"), header);
      }
    }
  }

  /**
   * The program as the README runs it, on a free port for a few seconds: the address it prints
   * serves the page while the robot drives, it ends by itself with exit code 0 and a summary, and
   * leaves no thread of its own behind.
   */
  @Test
  void theProgramPrintsAnAddressThatServesThePageAndEndsAfterItsSeconds() throws Exception {
    java.io.PipedInputStream piped = new java.io.PipedInputStream(1 << 16);
    PrintStream out = new PrintStream(new java.io.PipedOutputStream(piped), true, StandardCharsets.UTF_8);
    ByteArrayOutputStream err = new ByteArrayOutputStream();
    java.util.concurrent.ExecutorService program = java.util.concurrent.Executors.newSingleThreadExecutor();
    try {
      java.util.concurrent.Future<Integer> code = program.submit(() -> {
        try (out) {
          return WatchedRobot.run(new String[] {"--port", "0", "--seconds", "3"}, out,
              new PrintStream(err, true, StandardCharsets.UTF_8));
        }
      });
      java.io.BufferedReader lines =
          new java.io.BufferedReader(new java.io.InputStreamReader(piped, StandardCharsets.UTF_8));
      String watch = null;
      List<String> printed = new java.util.ArrayList<>();
      for (String line = lines.readLine(); line != null && printed.size() < 10; line = lines.readLine()) {
        printed.add(line);
        if (line.startsWith("watch it at ")) {
          watch = line;
          break;
        }
      }
      assertTrue(watch != null && watch.endsWith(" (for 3 s)"), "printed: " + printed + err);
      java.net.URI page = java.net.URI.create(watch.substring("watch it at ".length(), watch.indexOf(" (for")));
      assertEquals("127.0.0.1", page.getHost(), watch);
      java.net.HttpURLConnection get = (java.net.HttpURLConnection) page.resolve("/api/topology").toURL().openConnection();
      get.setConnectTimeout(5_000);
      get.setReadTimeout(10_000);
      try {
        assertEquals(200, get.getResponseCode(), watch);
        assertTrue(new String(get.getInputStream().readAllBytes(), StandardCharsets.UTF_8).contains("\"odometry\""));
      } finally {
        get.disconnect();
      }
      String rest = new String(piped.readAllBytes(), StandardCharsets.UTF_8); // until run() closes out
      assertEquals(0, code.get(30, java.util.concurrent.TimeUnit.SECONDS), rest + err);
      assertTrue(rest.matches("(?s)(at|not at) the goal after \\d+ steps; odometry says .*"), rest);
      Set<String> left = new HashSet<>();
      for (Thread thread : Thread.getAllStackTraces().keySet()) {
        if (thread.isAlive() && (thread.getName().startsWith("prime-inspector-robot")
            || thread.getName().equals("robot-driver"))) {
          left.add(thread.getName());
        }
      }
      assertEquals(Set.of(), left, "threads left after the program ended");
    } finally {
      program.shutdownNow();
    }
  }

  @Test
  void badArgumentsAndATakenPortAreExplained() throws Exception {
    ByteArrayOutputStream out = new ByteArrayOutputStream();
    ByteArrayOutputStream err = new ByteArrayOutputStream();
    PrintStream o = new PrintStream(out, true, StandardCharsets.UTF_8);
    PrintStream e = new PrintStream(err, true, StandardCharsets.UTF_8);
    assertEquals(2, WatchedRobot.run(new String[] {"--port", "70000"}, o, e));
    assertTrue(err.toString(StandardCharsets.UTF_8).contains("--port wants a whole number from 0 to 65535; got '70000'"),
        err.toString(StandardCharsets.UTF_8));
    err.reset();
    assertEquals(2, WatchedRobot.run(new String[] {"--fast"}, o, e));
    assertTrue(err.toString(StandardCharsets.UTF_8).contains("unknown argument '--fast'"));
    err.reset();
    try (ServerSocket taken = new ServerSocket(0, 1, InetAddress.getLoopbackAddress())) {
      assertEquals(3, WatchedRobot.run(new String[] {"--port", String.valueOf(taken.getLocalPort())}, o, e));
      assertTrue(err.toString(StandardCharsets.UTF_8).contains("cannot listen on"), err.toString(StandardCharsets.UTF_8));
    }
    assertFalse(out.toString(StandardCharsets.UTF_8).contains("watch it at"));
    assertEquals(0, WatchedRobot.run(new String[] {"--help"}, o, e));
    assertTrue(out.toString(StandardCharsets.UTF_8).contains("usage: watched-robot"));
  }
}
