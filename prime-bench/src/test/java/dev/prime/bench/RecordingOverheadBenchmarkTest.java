package dev.prime.bench;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import dev.prime.Recording;
import dev.prime.bench.report.Families;
import dev.prime.bench.report.Family;
import dev.prime.bench.report.RunSettings;
import dev.prime.bench.report.SuiteRunner;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.openjdk.jmh.results.RunResult;
import org.openjdk.jmh.runner.options.VerboseMode;

/**
 * {@link RecordingOverheadBenchmark} measures what it says: with {@code recordingOn} each row's
 * core records every transmission, with {@code recordingOff} it has no recording at all, and
 * every row computes what the FOR baseline computes. Then each recording row runs through JMH in
 * both scenarios (the suite's smoke test runs only a family's first scenario).
 */
class RecordingOverheadBenchmarkTest {
  private static final int SENT = 3;

  private static RecordingOverheadBenchmark.Setting setting(String scenario) {
    RecordingOverheadBenchmark.Setting setting = new RecordingOverheadBenchmark.Setting();
    setting.length = 4;
    setting.payload = 100;
    setting.scenario = scenario;
    setting.build();
    return setting;
  }

  /** Recorded values per name after {@link #SENT} transmissions, or empty with recording off. */
  private static Map<String, Long> recorded(PrimeCore core) {
    Map<String, Long> counts = new TreeMap<>();
    if (core.config().recording() == null) {
      assertThrows(IllegalStateException.class, core::recording);
      return counts;
    }
    Recording recording = core.recording();
    for (String name : recording.names()) {
      counts.put(name, recording.recorded(name));
    }
    return counts;
  }

  @Test
  void recordingOnRecordsEveryBlockOutputAndOffRecordsNothing() {
    for (String scenario : List.of("recordingOff", "recordingOn")) {
      boolean on = scenario.equals("recordingOn");
      RecordingOverheadBenchmark benchmark = new RecordingOverheadBenchmark();
      RecordingOverheadBenchmark.Setting setting = setting(scenario);
      WorkerCpuTime.PlainClock clock = new WorkerCpuTime.PlainClock();
      RecordingOverheadBenchmark.Direct direct = new RecordingOverheadBenchmark.Direct();
      direct.build(setting);
      RecordingOverheadBenchmark.Liberty liberty = new RecordingOverheadBenchmark.Liberty();
      liberty.build(setting);
      RecordingOverheadBenchmark.Radiant radiant = new RecordingOverheadBenchmark.Radiant();
      radiant.build(setting);
      RecordingOverheadBenchmark.Collected source = new RecordingOverheadBenchmark.Collected();
      source.build(setting);
      try {
        for (int i = 0; i < SENT; i++) {
          long expected = benchmark.forHandWritten(setting, direct, clock);
          // each call adds 1+2+3+4 to the same packet: every row sees the FOR result move by 10
          assertEquals(expected + 10, benchmark.liberty(setting, liberty, clock), scenario);
          assertEquals(expected + 20, benchmark.radiant(setting, radiant, clock), scenario);
          assertEquals(expected + 30, benchmark.primeSource(setting, source), scenario);
        }
        Map<String, Long> chains = recorded(liberty.core());
        assertEquals(on ? 4 : 0, chains.size(), scenario + " Liberty: " + chains);
        chains.values().forEach(count -> assertEquals(SENT, count, scenario + " " + chains));
        Map<String, Long> fused = recorded(radiant.core());
        assertEquals(on ? 4 : 0, fused.size(), scenario + " Radiant: " + fused);
        fused.values().forEach(count -> assertEquals(SENT, count, scenario + " " + fused));
        Map<String, Long> sourced = recorded(source.core());
        // the 4 adders and the event source; the collector's outputs are recorded too
        assertTrue(on ? sourced.size() >= 5 : sourced.isEmpty(), scenario + " sources: " + sourced);
        sourced.values().forEach(count -> assertEquals(SENT, count, scenario + " " + sourced));
      } finally {
        liberty.close();
        radiant.close();
        source.close();
      }
    }
  }

  @Test
  void anUnknownScenarioIsRefused() {
    IllegalArgumentException refused =
        assertThrows(IllegalArgumentException.class, () -> setting("recording"));
    assertTrue(refused.getMessage().contains("recordingOff or recordingOn"), refused.getMessage());
  }

  @Test
  @Timeout(value = 3, unit = TimeUnit.MINUTES)
  void everyRecordingRowRunsThroughJmhInBothScenarios() throws Exception {
    System.setProperty("jmh.ignoreLock", "true"); // this run measures nothing
    List<Family> rows =
        Families.ALL.stream().filter(f -> f.table().equals(Families.RECORDING)).toList();
    assertEquals(4, rows.size(), "FOR, Radiant, Liberty and sources");
    RunSettings bothScenarios =
        new RunSettings("smoke-both", 1, 0, 100, 1, 100, List.of("100"), true, false);

    List<RunResult> results = SuiteRunner.run(rows, bothScenarios, VerboseMode.SILENT);

    assertEquals(8, results.size(), "4 rows × 2 scenarios");
    for (RunResult result : results) {
      double score = result.getPrimaryResult().getScore();
      assertTrue(score > 0 && Double.isFinite(score), result.getParams().id() + " gave " + score);
    }
    assertEquals(
        List.of("recordingOff", "recordingOn"),
        results.subList(0, 2).stream().map(r -> r.getParams().getParam("scenario")).toList());
  }
}
