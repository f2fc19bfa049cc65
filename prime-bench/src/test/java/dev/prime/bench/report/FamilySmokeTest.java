package dev.prime.bench.report;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.List;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.openjdk.jmh.results.RunResult;
import org.openjdk.jmh.runner.RunnerException;
import org.openjdk.jmh.runner.options.VerboseMode;

/**
 * CI's guard against rotting benchmarks: every family of the suite runs once through JMH (its own
 * fork, no warm-up, one 100 ms iteration, 100 B, its first scenario) and must produce a time.
 * This checks that the benchmarks run and return, not how fast they are.
 */
class FamilySmokeTest {

  /**
   * JMH holds a machine-wide lock so that two measurements do not disturb each other. This run
   * measures nothing, so it must not fail (nor wait) because someone benchmarks on the same
   * machine.
   */
  @BeforeAll
  static void ignoreJmhLock() {
    System.setProperty("jmh.ignoreLock", "true");
  }

  @Test
  @Timeout(value = 3, unit = TimeUnit.MINUTES)
  void everyFamilyRunsAndProducesATime() throws RunnerException {
    List<RunResult> results = SuiteRunner.run(Families.ALL, RunSettings.SMOKE, VerboseMode.SILENT);
    assertEquals(Families.ALL.size(), results.size(), "one result per family");
    for (int i = 0; i < results.size(); i++) {
      RunResult result = results.get(i);
      assertEquals(Families.ALL.get(i).benchmarkName(), result.getParams().getBenchmark());
      double score = result.getPrimaryResult().getScore();
      assertTrue(score > 0 && Double.isFinite(score),
          Families.ALL.get(i).row() + " gave " + score);
      assertEquals("100", result.getParams().getParam("payload"));
    }
  }

  @Test
  void everyFamilyRunsInForksOfItsOwn() {
    for (Family family : Families.ALL) {
      for (RunSettings settings : List.of(RunSettings.QUICK, RunSettings.FULL, RunSettings.SMOKE)) {
        int forks =
            SuiteRunner.options(family, settings, VerboseMode.SILENT).build().getForkCount().get();
        assertTrue(forks >= 1, family.row() + " in " + settings.name() + ": " + forks + " forks");
      }
    }
  }
}
