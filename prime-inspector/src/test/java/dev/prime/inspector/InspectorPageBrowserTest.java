package dev.prime.inspector;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.Tick;
import dev.prime.liberty.LibertyCore;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.Hosting;
import dev.prime.optimus.OptimusCore;
import dev.prime.topology.TopologyNode;
import java.net.URI;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.TreeSet;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.Test;

/**
 * The page in a real browser: a headless Chromium, driven over the DevTools protocol, reads the
 * page's DOM. Skipped, with the reason, where no Chromium is installed.
 */
class InspectorPageBrowserTest {
  private static final Duration PATIENCE = Duration.ofSeconds(20);

  @BeforeEach
  void needsChromium() {
    HeadlessChromium.requireBinary();
  }

  private static CoreConfig recording() {
    return CoreConfig.builder().name("demo").recording(RecordingOptions.defaults()).build();
  }

  private static Set<String> drawnNames(PrimeCore core) {
    Set<String> names = new TreeSet<>();
    for (TopologyNode node : core.topology().nodes()) {
      if (!(node instanceof TopologyNode.Link)) {
        names.add(node.name());
      }
    }
    return names;
  }

  private static Set<String> names(JsonNode array) {
    Set<String> names = new TreeSet<>();
    array.forEach(name -> names.add(name.asText()));
    return names;
  }

  private static final String DRAWN =
      "[...document.querySelectorAll('#diagram g.node')].map(g => g.dataset.name)";

  private static String rateOf(String name) {
    return "(() => { const g = document.querySelector('#diagram g.node[data-name=\"" + name + "\"]');"
        + " return g && g.hasAttribute('data-rate') ? Number(g.getAttribute('data-rate')) : null; })()";
  }

  @Test
  void drawsEveryNodeAndTheRatesMoveWithTheController() throws Exception {
    try (PrimeCore core = new LibertyCore(recording());
        DemoController demo = new DemoController(core)) {
      core.start();
      try (PrimeInspector inspector = PrimeInspector.start(core)) {
        List<ProcessHandle> browserProcesses;
        try (HeadlessChromium chromium = HeadlessChromium.open(inspector.uri(), 1400, 900)) {
          Set<String> expected = drawnNames(core);
          assertTrue(expected.containsAll(core.serviceNames()), "every service is drawn: " + expected);
          JsonNode drawn =
              chromium.await(DRAWN, names -> names.size() == expected.size(), PATIENCE,
                  "the diagram should draw " + expected.size() + " nodes " + expected);
          assertEquals(expected, names(drawn));

          // a declaration made while the page is open is drawn too
          core.source("late", new EventBlock<String>()).then(core.chain("shout", (String s) -> s + "!"));
          JsonNode redrawn =
              chromium.await(DRAWN, names -> names.size() == expected.size() + 3, PATIENCE,
                  "the diagram should be laid out again with the late source, chain and output");
          assertTrue(names(redrawn).containsAll(Set.of("late", "shout", "late>shout")), redrawn.toString());

          demo.drive(5);
          JsonNode moving =
              chromium.await(rateOf("odometry"), rate -> rate.isNumber() && rate.asDouble() > 10,
                  PATIENCE, "odometry's rate should rise above 10/s while the controller runs");
          JsonNode total =
              chromium.evaluate(
                  "Number(document.querySelector('#diagram g.node[data-name=\"pid\"]').getAttribute('data-total'))");
          assertTrue(total.asLong() > 0, "pid's total shown: " + total);
          String shown =
              chromium.evaluate(
                  "document.querySelector('#diagram g.node[data-name=\"odometry\"] .figures').textContent").asText();
          assertTrue(shown.matches("[0-9.]+/s · [0-9]+ in all"), "odometry's figures read: " + shown);

          demo.stop();
          chromium.await(rateOf("odometry"), rate -> rate.isNumber() && rate.asDouble() == 0.0,
              PATIENCE, "odometry's rate should fall back to 0 once the controller stops (it was "
                  + moving + ")");
          browserProcesses = chromium.processes();
          assertFalse(browserProcesses.isEmpty());
        }
        for (ProcessHandle process : browserProcesses) {
          assertFalse(process.isAlive(), "Chromium process " + process.pid() + " outlived the test");
        }
      }
    }
  }

  private static String attribute(String name, String attribute) {
    return "(() => { const g = document.querySelector('#diagram g.node[data-name=\"" + name + "\"]');"
        + " return g && g.hasAttribute('" + attribute + "') ? Number(g.getAttribute('" + attribute
        + "')) : null; })()";
  }

  @Test
  void withMetricsOnShowsProcessingTimesAndFailures() throws Exception {
    CoreConfig config =
        CoreConfig.builder().name("metered").metrics(true).recording(RecordingOptions.defaults()).build();
    try (PrimeCore core = new LibertyCore(config);
        DemoController demo = new DemoController(core)) {
      core.start();
      demo.drive(5);
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium = HeadlessChromium.open(inspector.uri(), 1400, 900)) {
        chromium.await(attribute("odometry", "data-latencyms"), ms -> ms.isNumber() && ms.asDouble() > 0,
            PATIENCE, "odometry's processing time should be shown");
        chromium.await(rateOf("pid"), rate -> rate.isNumber() && rate.asDouble() > 10, PATIENCE,
            "pid's rate should be shown above 10/s");
        JsonNode errors =
            chromium.await(attribute(DemoController.LISTENER, "data-errors"),
                e -> e.isNumber() && e.asLong() > 0, PATIENCE,
                "the failing listener's errors should be counted on the page");
        assertTrue(errors.asLong() <= core.metrics().service(DemoController.LISTENER).failures(),
            "the page shows no more failures than the metrics counted");
        String shown =
            chromium.evaluate(
                "document.querySelector('#diagram g.node[data-name=\"pid\"] .figures').textContent").asText();
        assertTrue(shown.matches("[0-9.]+/s · [0-9.e+-]+ (ms|µs|ns) · 0 err"), "pid's figures read: " + shown);
        assertTrue(
            chromium.evaluate("document.getElementById('figures-note').textContent").asText()
                .startsWith("Figures from the core's metrics"));
        assertTrue(
            chromium.evaluate("document.querySelector('#diagram g.node[data-name=\"" + DemoController.LISTENER
                + "\"]').classList.contains('failing')").asBoolean(),
            "a failing node is marked");
      } finally {
        demo.stop();
      }
    }
  }

  @Test
  void plotsTheNumericFieldsOfTheChosenName() throws Exception {
    try (PrimeCore core = new LibertyCore(recording());
        DemoController demo = new DemoController(core)) {
      core.start();
      demo.drive(5);
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium =
              HeadlessChromium.open(inspector.uri().resolve("/#plot=odometry"), 1400, 900)) {
        JsonNode fields =
            chromium.await(
                "[...document.querySelectorAll('#plot polyline.series')]"
                    + ".filter(p => Number(p.dataset.points) >= 2).map(p => p.dataset.field)",
                f -> f.size() == 3, PATIENCE,
                "odometry's three fields (x, y, moving) should be plotted with two points or more");
        assertEquals(Set.of("x", "y", "moving"), names(fields));
        assertEquals("odometry", chromium.evaluate("document.getElementById('plot-choice').value").asText());
        assertTrue(
            chromium.evaluate("document.getElementById('recording-off').hidden").asBoolean(),
            "recording is on: no notice");

        // choosing another name in the page plots that one instead
        chromium.evaluate(
            "(() => { const s = document.getElementById('plot-choice'); s.value = 'pid';"
                + " s.dispatchEvent(new Event('change')); return true; })()");
        JsonNode pid =
            chromium.await(
                "[...document.querySelectorAll('#plot polyline.series')]"
                    + ".filter(p => Number(p.dataset.points) >= 2).map(p => p.dataset.field)",
                f -> names(f).equals(Set.of("leftVolts", "rightVolts")), PATIENCE,
                "pid's fields should be plotted after choosing it");
        assertEquals(2, pid.size());
        demo.stop();
      }
    }
  }

  /** A gauge whose level is unknown (NaN) every other step, and a reading that is never finite. */
  record Gauge(long step, double level, double unknown) {}

  private static String pointsOf(String field) {
    return "(() => { const p = document.querySelector('#plot polyline.series[data-field=\"" + field + "\"]');"
        + " return p ? p.getAttribute('points') : null; })()";
  }

  /**
   * NaN and the infinities, which JSON has not, come to the page as null: the plot leaves those
   * values out. It drew them as 0, a value the source never gave.
   */
  @Test
  void valuesThatAreNoNumberAreLeftOutOfThePlotNotDrawnAsZero() throws Exception {
    try (PrimeCore core = new LibertyCore(recording())) {
      EventBlock<Long> steps = new EventBlock<>();
      core.source("steps", steps).then(core.chain("gauge",
          (Long s) -> new Gauge(s, s % 2 == 0 ? 5.0 : Double.NaN, Double.POSITIVE_INFINITY)));
      core.start();
      for (long s = 1; s <= 20; s++) {
        steps.publish(s);
      }
      assertEquals(20, waitForRecorded(core, "gauge", 20), "values gauge recorded");
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium =
              HeadlessChromium.open(URI.create(inspector.uri() + "#plot=gauge"), 1200, 800)) {
        JsonNode level =
            chromium.await(pointsOf("level"), p -> p.isTextual() && p.asText().split(" ").length >= 2,
                PATIENCE, "gauge's level should be plotted");
        Set<String> heights = new TreeSet<>();
        for (String point : level.asText().split(" ")) {
          heights.add(point.split(",")[1]);
        }
        assertEquals(1, heights.size(),
            "every level given is 5.0, so every point drawn lies at one height: " + level.asText());
        assertEquals("", chromium.evaluate(pointsOf("unknown")).asText(),
            "a field that was never a finite number has no point drawn");
      }
    }
  }

  /** The seconds back to which the plot reaches: its time axis' leftmost label, "-12.5 s". */
  private static final String PLOTTED_SECONDS =
      "(() => { const t = [...document.querySelectorAll('#plot text.tick')]"
          + ".find(e => e.getAttribute('text-anchor') === 'start');"
          + " return t ? Number(t.textContent.replace(/^-| s$/g, '')) : null; })()";

  /**
   * The plot keeps the last minute of recorded time however fast the values come: a name recorded
   * a thousand times a second (the stream sends up to 300 values an event, two events a second)
   * is plotted back to its first values after twelve seconds, not over its last few seconds only.
   */
  @Test
  void aNameRecordedManyTimesASecondIsPlottedOverTheLastMinute() throws Exception {
    try (PrimeCore core = new LibertyCore(recording())) {
      core.timer("fast", Duration.ofMillis(1))
          .then(core.chain("level", (Tick tick) -> (double) (tick.count() % 100)));
      core.start();
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium =
              HeadlessChromium.open(URI.create(inspector.uri() + "#plot=level"), 1200, 800)) {
        chromium.await(pointsOf("value"), p -> p.isTextual() && p.asText().split(" ").length >= 2,
            PATIENCE, "level's values should be plotted");
        long start = System.nanoTime();
        JsonNode reach =
            chromium.await(PLOTTED_SECONDS, s -> s.isNumber() && s.asDouble() >= 12,
                Duration.ofSeconds(45),
                "the plot should reach back 12 s once the page has received 12 s of values");
        double streamed = (System.nanoTime() - start) / 1e9;
        assertTrue(reach.asDouble() <= streamed + 1,
            "the plot reaches back " + reach + " s, the page received values for " + streamed + " s");
      }
    }
  }

  private static String drawnElsewhere(String name) {
    return "(() => { const g = document.querySelector('#diagram g.node[data-name=\"" + name + "\"]');"
        + " return g ? g.classList.contains('elsewhere') : null; })()";
  }

  private static OptimusCore orderedHost(String redis, String... hosts) {
    OptimusCore.Builder builder =
        OptimusCore.builder()
            .config(CoreConfig.builder().name("pair").metrics(true).build())
            .redis(redis)
            .leaseTime(Duration.ofSeconds(1))
            .hosting("ordered", Hosting.ORDERED);
    OptimusCore core = (hosts.length == 0 ? builder : builder.hosts(hosts)).build();
    core.source("numbers", new EventBlock<Integer>()).then(core.chain("ordered", (Integer x) -> x));
    return core;
  }

  /**
   * A service another process runs is drawn dashed, and drawn again when that changes: on the page
   * of an Optimus standby of an ordered service, the service is drawn as hosted here once the
   * standby has taken it over from the process that ran it.
   */
  @Test
  void aServiceTakenOverFromAnotherProcessIsDrawnAgainAsHostedHere() throws Exception {
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        OptimusCore standby = orderedHost(redis.getUri())) {
      OptimusCore active = orderedHost(redis.getUri(), "ordered");
      try {
        active.start();
        standby.start();
        try (PrimeInspector inspector = PrimeInspector.start(standby);
            HeadlessChromium chromium = HeadlessChromium.open(inspector.uri(), 1200, 800)) {
          chromium.await(drawnElsewhere("ordered"), JsonNode::asBoolean, PATIENCE,
              "'ordered' should be drawn dashed while the active process runs it");
          active.close();
          assertTrue(awaitHosted(standby, "ordered"), "the standby took 'ordered' over");
          chromium.await(drawnElsewhere("ordered"), v -> v.isBoolean() && !v.asBoolean(), PATIENCE,
              "'ordered' should be drawn as hosted here once the standby took it over");
        }
      } finally {
        active.close();
      }
    }
  }

  private static boolean awaitHosted(PrimeCore core, String service) throws InterruptedException {
    long deadline = System.nanoTime() + PATIENCE.toNanos();
    while (!core.serviceNames().contains(service) && System.nanoTime() < deadline) {
      Thread.sleep(10); // polling the core, bounded by the deadline
    }
    return core.serviceNames().contains(service);
  }

  private static long waitForRecorded(PrimeCore core, String name, long count) throws InterruptedException {
    long deadline = System.nanoTime() + PATIENCE.toNanos();
    while (core.recording().recorded(name) < count && System.nanoTime() < deadline) {
      Thread.sleep(10); // polling the recording, bounded by the deadline
    }
    return core.recording().recorded(name);
  }

  @Test
  void saysSoWhenRecordingIsOffAndStillDrawsTheDiagram() throws Exception {
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(CoreConfig.builder().name("quiet").build()))) {
      core.start();
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium = HeadlessChromium.open(inspector.uri(), 1200, 800)) {
        Set<String> expected = drawnNames(core);
        chromium.await(DRAWN, names -> names.size() == expected.size(), PATIENCE,
            "the diagram should draw " + expected);
        JsonNode notice =
            chromium.await(
                "(() => { const n = document.getElementById('recording-off');"
                    + " return n.hidden ? null : n.textContent; })()",
                text -> text.isTextual(), PATIENCE, "the page should say recording is off");
        assertTrue(notice.asText().contains("Recording is off"), notice.asText());
        assertTrue(notice.asText().contains("RecordingOptions.defaults()"), notice.asText());
        assertTrue(chromium.evaluate("document.getElementById('plot-choice').disabled").asBoolean());
        chromium.await("document.getElementById('state').textContent", s -> s.asText().startsWith("running"),
            PATIENCE, "the figures stream should still say the core runs");
      }
    }
  }

  @Test
  void aNameThePageCannotPlotIsExplained() throws Exception {
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(recording()))) {
      core.start();
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium =
              HeadlessChromium.open(URI.create(inspector.uri() + "#plot=nowhere"), 1200, 800)) {
        JsonNode status =
            chromium.await("document.getElementById('plot-status').textContent",
                s -> s.asText().contains("nowhere"), PATIENCE,
                "the page should explain why 'nowhere' cannot be plotted");
        assertTrue(status.asText().contains("has no service, source or chain named 'nowhere'"),
            status.asText());
      }
    }
  }
}
