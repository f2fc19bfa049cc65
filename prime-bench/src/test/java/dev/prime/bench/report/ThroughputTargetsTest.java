package dev.prime.bench.report;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.bench.report.TargetVerdict.Outcome;
import java.io.IOException;
import java.net.URISyntaxException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** The throughput targets judged on a small, hand-written results file (targets-fixture.json). */
class ThroughputTargetsTest {
  private static List<TargetVerdict> verdicts;

  @BeforeAll
  static void judge() throws IOException, URISyntaxException {
    Path fixture =
        Path.of(ThroughputTargetsTest.class.getResource("/targets-fixture.json").toURI());
    verdicts = ThroughputTargets.judge(Score.readAll(fixture));
  }

  private static TargetVerdict verdict(String target) {
    return verdicts.stream()
        .filter(v -> v.target().equals(target))
        .findFirst()
        .orElseThrow(() -> new AssertionError("no verdict for " + target + " in " + verdicts));
  }

  @Test
  void readsEachForksMeanInNanosecondsOrValuesPerSecond() throws IOException, URISyntaxException {
    List<Score> scores =
        Score.readAll(Path.of(getClass().getResource("/targets-fixture.json").toURI()));
    Score prime = scores.get(0);
    assertEquals(List.of(100.0, 120.0, 300.0), prime.forkMeans());
    Score sync = scores.get(4);
    assertEquals(350.0, sync.value(), 1e-9); // written in us/op
    Score fourHops = scores.get(8);
    assertTrue(fourHops.throughput());
    assertEquals(140_000.0, fourHops.value(), 1e-9); // written in ops/ms
  }

  @Test
  void aSlowForkFailsStabilityEvenWhenTheMeanLooksFine() {
    TargetVerdict stable = verdict("slowest fork of Prime sources ≤ 1.5× the fastest, 100 B");
    assertEquals(Outcome.NOT_MET, stable.outcome());
    assertTrue(stable.measured().contains("100, 120, 300; 3.00×"), stable.measured());
    assertEquals(Outcome.MET,
        verdict("slowest fork of Prime sources ≤ 1.5× the fastest, 1 KB").outcome());
  }

  @Test
  void ratiosAgainstPeersGoTheRightWay() {
    // 150 ns against the Disruptor's 60: 2.5×, more than 2×
    assertEquals(Outcome.NOT_MET,
        verdict("Prime sources ≤ 2× the LMAX Disruptor, 100 B").outcome());
    // 110 against 50: 2.2×
    assertEquals(Outcome.NOT_MET,
        verdict("Prime sources ≤ 2× the LMAX Disruptor, 1 KB").outcome());
    // Kotlin 300 ns is 2× Prime's 150: met; Reactor 200 is 1.33×: not met
    assertEquals(Outcome.MET,
        verdict("Kotlin Channels ≥ 1.5× Prime sources' time, 100 B").outcome());
    assertEquals(Outcome.NOT_MET,
        verdict("Reactor publishOn ≥ 1.5× Prime sources' time, 100 B").outcome());
  }

  @Test
  void allocationAndTheSynchronousRow() {
    assertEquals(Outcome.MET, verdict("0 B allocated per value, 100 B").outcome());
    assertEquals(Outcome.NOT_MET, verdict("0 B allocated per value, 1 KB").outcome());
    assertEquals(Outcome.MET,
        verdict("synchronous Prime-sources row ≤ 0.4 µs, 100 B").outcome());
  }

  @Test
  void optimusFlowsAndCalls() {
    assertEquals(Outcome.MET,
        verdict("optimusFlow ≥ 400,000 values/s through one hop, 100 B").outcome());
    assertEquals(Outcome.NOT_MET,
        verdict("optimusFlow ≥ 150,000 values/s through four hops, 100 B").outcome());
    assertEquals(Outcome.MET,
        verdict("optimusCall ≤ 1.1× the raw Jedis echo loop, 1hop, 100 B").outcome());
    assertEquals(Outcome.NOT_MEASURED,
        verdict("optimusCall ≤ 1.1× the raw Jedis echo loop, 4hops, 100 B").outcome());
  }

  @Test
  void callsRunInRoundsAreJudgedOnTheMeanOfAllRoundsNotTheFirst() {
    Map<String, String> oneHop = Map.of("payload", "100", "scenario", "1hop");
    // the first round alone would be 1.00×; all three: 130 against 100
    List<Score> rounds = List.of(
        call("optimusCall", oneHop, 100_000), call("rawCall", oneHop, 100_000),
        call("rawCall", oneHop, 90_000), call("optimusCall", oneHop, 150_000),
        call("optimusCall", oneHop, 140_000), call("rawCall", oneHop, 110_000));
    TargetVerdict pooled = ThroughputTargets.judge(rounds).stream()
        .filter(v -> v.target().equals("optimusCall ≤ 1.1× the raw Jedis echo loop, 1hop, 100 B"))
        .findFirst().orElseThrow();
    assertEquals(Outcome.NOT_MET, pooled.outcome());
    assertEquals("130,000.0 ns (3 rounds: 100,000, 150,000, 140,000) against 100,000.0 ns"
        + " (3 rounds: 100,000, 90,000, 110,000): 1.30×", pooled.measured());
  }

  private static Score call(String method, Map<String, String> params, double nanos) {
    return new Score("dev.prime.bench.OptimusBenchmark." + method, params, nanos, nanos / 10,
        false, List.of(nanos), Double.NaN);
  }

  @Test
  void competingConsumersSpeedUp() {
    // 1700 / 900 = 1.89 ≥ 1.8; 2700 / 900 = 3.0 ≥ 2.6
    TargetVerdict two = verdict("2 hosts ≥ 1.8× one host's values/s (a 1 ms block)");
    assertEquals(Outcome.MET, two.outcome());
    assertEquals("1,700 ± 10 values/s against 900 ± 10 values/s: 1.89×", two.measured());
    assertEquals(Outcome.MET,
        verdict("3 hosts ≥ 2.6× one host's values/s (a 1 ms block)").outcome());
  }

  @Test
  void aBenchmarkMissingFromTheRunIsNotMeasuredNotMet() {
    assertEquals(Outcome.NOT_MEASURED,
        verdict("Prime sources ≤ 2× the LMAX Disruptor, 10 KB").outcome());
    assertEquals(Outcome.NOT_MEASURED,
        verdict("slowest fork of Prime sources ≤ 1.5× the fastest, 10 KB").outcome());
  }

  @Test
  void theTwoHandOffRowIsReportedForInformationAndNeverJudged() throws IOException,
      URISyntaxException {
    List<Score> scores =
        Score.readAll(Path.of(getClass().getResource("/targets-fixture.json").toURI()));
    String information = ThroughputTargets.information(scores);
    assertTrue(information.contains("- 100 B: 400.0 ± 30.0 ns"), information);
    assertTrue(information.contains("- 1 KB: no result in this run"), information);
    // the machine's own spread: the Disruptor's forks (50 and 70 ns), a bare round trip's (100, 400)
    assertTrue(information.contains("- the Disruptor, 100 B: 2 forks, ns: 50, 70; 1.40×"), information);
    assertTrue(information.contains("- the Disruptor, 1 KB: fewer than 2 forks in this run"),
        information);
    assertTrue(information.contains("- a core-to-core round trip: 2 forks, ns: 100, 400; 4.00×"),
        information);
    // the judged Prime row is primeSource alone: the fixture's primeSource is 150 ns, not 400
    assertTrue(verdict("Prime sources ≤ 2× the LMAX Disruptor, 100 B").measured()
        .startsWith("150.0"), verdict("Prime sources ≤ 2× the LMAX Disruptor, 100 B").measured());
    assertTrue(verdicts.stream().noneMatch(v -> v.measured().contains("400.0")), verdicts::toString);
  }

  @Test
  void theSynchronousRowIsReportedBesideItsFloorAndNeverJudgedAgainstIt() {
    Map<String, String> at100 = Map.of("payload", "100", "scenario", "monomorphic", "length", "4");
    Score floor = new Score("dev.prime.bench.CoreRoundTripBenchmark.roundTripWithPacket", Map.of(),
        600, 40, false, List.of(550.0, 650.0), Double.NaN);
    Score row = new Score("dev.prime.bench.SyncSourceBenchmark.primeSource", at100, 660, 30,
        false, List.of(660.0), 0.0);
    String information = ThroughputTargets.information(List.of(floor, row));
    assertTrue(information.contains("- the floor: 600.0 ± 40.0 ns; 2 forks, ns: 550, 650; 1.18×"),
        information);
    assertTrue(information.contains("- the synchronous row, 100 B: 660.0 ± 30.0 ns, 1.10× the floor"),
        information);
    assertTrue(information.contains("- the synchronous row, 1 KB: no result in this run"), information);
    // the bare round trip is not the floor: a run without the packet's round trip says so
    Score bare = new Score("dev.prime.bench.CoreRoundTripBenchmark.roundTrip", Map.of(),
        270, 10, false, List.of(270.0, 270.0), Double.NaN);
    String withoutFloor = ThroughputTargets.information(List.of(bare, row));
    assertTrue(withoutFloor.contains("- the floor: no result in this run"), withoutFloor);
    assertTrue(withoutFloor.contains("- the synchronous row, 100 B: 660.0 ± 30.0 ns\n"), withoutFloor);
    // the target stays 0.4 µs whatever the floor
    assertEquals(Outcome.NOT_MET, ThroughputTargets.judge(List.of(floor, row)).stream()
        .filter(v -> v.target().equals("synchronous Prime-sources row ≤ 0.4 µs, 100 B"))
        .findFirst().orElseThrow().outcome());
  }

  @Test
  void theReportCountsWhatIsMetAndRefusesAForeignFile(@TempDir Path dir) throws IOException {
    String markdown = ThroughputTargets.render(verdicts, null);
    long met = verdicts.stream().filter(v -> v.outcome() == Outcome.MET).count();
    assertTrue(markdown.startsWith(met + " of " + verdicts.size() + " targets met."), markdown);
    assertEquals(verdicts.size() + 2 + 2, markdown.split("\n").length);
    Path notJmh = dir.resolve("other.json");
    Files.writeString(notJmh, "{\"benchmark\": 1}");
    IllegalArgumentException refused =
        assertThrows(IllegalArgumentException.class, () -> Score.readAll(notJmh));
    assertTrue(refused.getMessage().contains("not JMH's JSON"), refused.getMessage());
  }
}
