package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import java.util.SortedSet;
import java.util.TreeMap;
import java.util.TreeSet;
import java.util.stream.Collectors;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;

/**
 * Runs the jcstress tests of the in-memory source as part of {@code verify} (a short mode, about a
 * minute on 2 cores; {@code -Dprime.jcstress=long} for jcstress's default mode in every JIT
 * configuration it detects). The build fails on any forbidden or unknown outcome, any test error
 * or timeout, and any test that did not run; a deliberately racy toy, run in the same jcstress
 * run, proves that such a failure is reported.
 */
class JcstressRunTest {
  /**
   * The tests over Prime's classes: every {@code dev.prime.MemorySource*Stress}, {@code
   * dev.prime.Isolate*Stress} and {@code dev.prime.ServiceMeter*Stress} class.
   */
  static final String SUITE = "^dev\\.prime\\.(MemorySource|Isolate|ServiceMeter).*Stress$";

  private static final String TOY_NAME = "dev.prime.selfcheck.UnlockedClaimToy";

  private static final int SUITE_SIZE = 22;

  private static SortedSet<String> suite;
  private static Map<String, JcstressRun.Verdict> verdicts;

  private static boolean longMode() {
    return "long".equals(System.getProperty("prime.jcstress"));
  }

  /**
   * jcstress's options for this run. Short: its quick preset, one iteration of half a second per
   * fork, no split compilation (which would run each test in every pairing of interpreter, C1 and
   * C2 per actor); jcstress still runs each test with and without biased locking. Long: its
   * default preset in every configuration it detects.
   */
  private static List<String> mode() {
    return longMode()
        ? List.of("-m", "default")
        : List.of("-m", "quick", "-sc", "false", "-iters", "1", "-time", "500",
            "-jvmArgs", "-Xmx256m -XX:+UseSerialGC");
  }

  /** One jcstress run for the suite and the toy: jcstress probes the JVM for ~20 s per run. */
  @BeforeAll
  static void runJcstress() throws Exception {
    suite = JcstressRun.tests(SUITE);
    String filter = SUITE + "|^" + TOY_NAME.replace(".", "\\.") + "$";
    long start = System.nanoTime();
    verdicts = JcstressRun.run(filter, mode(), Path.of("jcstress-report"));
    long seconds = (System.nanoTime() - start) / 1_000_000_000L;
    verdicts.values().forEach(v -> System.out.println("jcstress " + v));
    System.out.println(
        "jcstress " + (longMode() ? "long" : "short") + " mode: " + verdicts.size() + " tests in "
            + seconds + " s");
  }

  @Test
  void theSuiteKeepsItsPromisesUnderEveryInterleaving() {
    assertEquals(SUITE_SIZE, suite.size(), "the suite's filter selects: " + suite);
    Map<String, JcstressRun.Verdict> ours = new TreeMap<>(verdicts);
    ours.remove(TOY_NAME);
    assertEquals(suite, new TreeSet<>(ours.keySet()), "every selected test reported results");
    List<String> failed =
        ours.values().stream()
            .filter(v -> !v.ok())
            .map(v -> v.test() + " " + v.status() + " " + v.counts() + " " + v.failures())
            .collect(Collectors.toList());
    assertTrue(failed.isEmpty(), "jcstress failures:\n" + String.join("\n", failed));
  }

  @Test
  void aRacyToyIsReportedForbidden() {
    JcstressRun.Verdict toy = verdicts.get(TOY_NAME);
    assertTrue(toy != null && toy.samples() > 0, "the toy ran: " + verdicts.keySet());
    assertFalse(toy.passed(), "the duplicate claim was caught: " + toy.counts());
    assertFalse(toy.ok(), "the runner's verdict fails it");
    long duplicates =
        toy.counts().getOrDefault("0, 0 (Forbidden)", 0L)
            + toy.counts().getOrDefault("1, 1 (Forbidden)", 0L);
    assertTrue(duplicates > 0, "duplicate claims counted as forbidden: " + toy.counts());
  }
}
