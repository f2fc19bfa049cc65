package dev.prime.bench.report;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.awt.image.BufferedImage;
import java.io.IOException;
import java.net.URISyntaxException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import javax.imageio.ImageIO;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** The tables and charts of a small, hand-written results file (table1-fixture.json). */
class ReportFromFixtureTest {
  private static Path fixture;

  @BeforeAll
  static void headless() throws URISyntaxException {
    System.setProperty("java.awt.headless", "true");
    fixture = Path.of(ReportFromFixtureTest.class.getResource("/table1-fixture.json").toURI());
  }

  private static List<ResultTable> tables() throws IOException {
    return ResultTable.build(Families.ALL, ResultsFile.read(fixture));
  }

  @Test
  void readsScoresInMicrosecondsWithAllocation() throws IOException {
    List<Measurement> measurements = ResultsFile.read(fixture);
    assertEquals(11, measurements.size());
    Measurement flow = measurements.get(5);
    assertEquals("dev.prime.bench.SyncPeerBenchmark.kotlinFlow", flow.benchmark());
    assertEquals(0.5, flow.micros(), 1e-12); // written in us/op
    assertEquals(160.0, flow.bytes(), 1e-12);
    Measurement radiant = measurements.get(3);
    assertEquals(0.001, radiant.micros(), 1e-12); // 1.0 ns/op
    assertTrue(Double.isNaN(radiant.errorMicros())); // JMH's "NaN"
    assertTrue(Double.isNaN(measurements.get(6).bytes())); // not profiled
  }

  @Test
  void readsTheEnvironmentRecordedWithTheResults() throws IOException {
    Environment environment = ResultsFile.environment(fixture);
    assertEquals(2, environment.cpus());
    assertEquals("2026-11-23T01:00:00Z", environment.date());
    assertEquals(0.75, environment.loadAfter(), 1e-12);
  }

  @Test
  void groupsByTableAndScenarioAndSkipsEmptyTables() throws IOException {
    List<ResultTable> tables = tables();
    assertEquals(
        List.of("Synchronous mode (monomorphic)", "Synchronous mode (polluted)",
            "Asynchronous mode"),
        tables.stream().map(ResultTable::title).toList());
    assertEquals(List.of("100", "1024"), tables.get(0).columns());
    assertEquals(List.of("100"), tables.get(1).columns());
    assertEquals(List.of("10240"), tables.get(2).columns());
  }

  @Test
  void computesEachCellsRatioToTheBaselineOfItsColumn() throws IOException {
    ResultTable sync = tables().get(0);
    ResultTable.Row radiant = sync.rows().get(1);
    assertEquals("Radiant chains", radiant.label());
    assertEquals(0.75, radiant.cells().get(0).ratio(), 1e-12);
    assertEquals(0.5, radiant.cells().get(1).ratio(), 1e-12);
    assertNull(sync.rows().get(2).cells().get(1)); // Liberty, 1 KB: not measured
    ResultTable async = tables().get(2);
    assertTrue(Double.isNaN(async.rows().get(6).cells().get(0).ratio())); // no FOR measured
  }

  @Test
  void writesTheMarkdownTableLikeThePapers() throws IOException {
    List<ResultTable> tables = tables();
    String md = MarkdownTables.render(tables, ResultsFile.environment(fixture));
    assertTrue(md.startsWith("Run 2026-11-23T01:00:00Z on 2 CPUs (Test CPU)"), md);
    assertTrue(md.contains("load average 0.50 at start, 0.75 at end"), md);
    int legend = md.indexOf("- **FOR**: the baseline row");
    int polluted = md.indexOf("- **polluted**: ten other chains");
    int firstTable = md.indexOf("### ");
    assertTrue(legend > 0 && polluted > 0 && legend < firstTable && polluted < firstTable, md);
    assertTrue(md.contains(
        "### Synchronous mode (monomorphic), µs per transmission\n\n"
            + "| | 100 B | 1 KB |\n|---|---|---|\n"
            + "| FOR | 0.00200 ± 0.00050 (1.00×) | 0.00200 ± 0.00025 (1.00×) |\n"
            + "| Radiant chains | 0.00150 ± 0.00020 (0.75×) | 0.00100 (0.50×) |\n"
            + "| Liberty chains | 0.00700 ± 0.00100 (3.50×) | — |\n"
            + "| Prime sources + collector | — | — |\n"
            + "| Kotlin Flow | 0.500 ± 0.010 (250×) | — |\n"), md);
    assertTrue(md.contains("| Kotlin Flow | 160.0 | — |"), md);
    assertTrue(md.contains("| Liberty chains | 0.0600 ± 0.0050 (15×) |"), md);
    assertTrue(md.contains("| | 10 KB |"), md);
    assertTrue(md.contains("| Prime sources (Liberty chain linked) | 0.150 ± 0.020 |"), md);
    assertFalse(md.contains("Synchronous mode (polluted), bytes allocated"), md); // not profiled
    assertFalse(md.contains("ignored"), md);
  }

  @Test
  void chartsEveryMeasuredRowAsPointsOnALogAxisWithItsErrorBar() throws IOException {
    ChartModel chart = Charts.chart(tables().get(0));
    assertEquals(ChartModel.Scale.LOG, chart.scale()); // 0.001 to 0.5 µs: 500× apart
    assertEquals(
        List.of("FOR (baseline)", "Radiant chains", "Liberty chains", "Kotlin Flow"),
        chart.series().stream().map(ChartModel.Series::label).toList());
    assertEquals(List.of("100 B", "1 KB"), chart.groups());
    ChartModel.Series radiant = chart.series().get(1);
    ChartModel.Mark measured = radiant.marks().get(0); // 1.5 ± 0.2 ns
    assertEquals(0.0015, measured.value(), 1e-12);
    assertEquals(0.0013, measured.low(), 1e-12);
    assertEquals(0.0017, measured.high(), 1e-12);
    assertTrue(measured.hasError());
    ChartModel.Mark single = radiant.marks().get(1); // 1.0 ns, error NaN
    assertFalse(single.hasError());
    assertEquals(single.value(), single.low(), 0);
    assertEquals(single.value(), single.high(), 0);
    assertNull(chart.series().get(2).marks().get(1)); // Liberty, 1 KB: not measured
    assertEquals(0.001, chart.axisMin(), 1e-12);
    assertEquals(1.0, chart.axisMax(), 1e-12);
    assertEquals(List.of(0.001, 0.01, 0.1, 1.0), chart.ticks());
  }

  @Test
  void writesOnePngPerTableAndTheMarkdownLinksThem(@TempDir Path out) throws IOException {
    List<Path> written = Table1.report(fixture, out);
    assertEquals(
        List.of(out.resolve("table1.md"), out.resolve("synchronous-mode-monomorphic.png"),
            out.resolve("synchronous-mode-polluted.png"), out.resolve("asynchronous-mode.png")),
        written);
    BufferedImage image = ImageIO.read(written.get(1).toFile());
    assertEquals(1000, image.getWidth());
    assertEquals(560, image.getHeight());
    String md = Files.readString(written.get(0));
    assertTrue(md.contains("![asynchronous-mode.png](asynchronous-mode.png)"), md);
  }

  @Test
  void rejectsResultsThatAreNotTimes(@TempDir Path out) throws IOException {
    Path json = out.resolve("throughput.json");
    Files.writeString(json, "[{\"benchmark\":\"x.y\",\"primaryMetric\":"
        + "{\"score\":1,\"scoreError\":0,\"scoreUnit\":\"ops/s\"}}]");
    IllegalArgumentException e =
        assertThrows(IllegalArgumentException.class, () -> ResultsFile.read(json));
    assertTrue(e.getMessage().contains("AverageTime"), e.getMessage());
  }
}
