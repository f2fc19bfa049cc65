package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import java.util.SortedSet;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;

/**
 * Runs the jcstress tests of the in-memory source as part of {@code verify}: jcstress's sanity
 * mode by default (about a minute on 2 cores), its default mode with {@code -Dprime.jcstress=long}.
 * The build fails on any forbidden or unknown outcome, any test error or timeout, and any test
 * that did not run; a deliberately racy toy proves that such a failure is reported.
 */
class JcstressRunTest {
  /** The tests over Prime's classes: every {@code dev.prime.*Stress} class and nested class. */
  private static final String SUITE = "^dev\\.prime\\.MemorySource.*Stress$";

  private static final String TOY = "^dev\\.prime\\.selfcheck\\.UnlockedClaimToy$";

  private static final int SUITE_SIZE = 11;

  private static String mode() {
    return "long".equals(System.getProperty("prime.jcstress")) ? "default" : "sanity";
  }

  @Test
  void memorySourceKeepsItsPromisesUnderEveryInterleaving() throws Exception {
    SortedSet<String> tests = JcstressRun.tests(SUITE);
    assertEquals(SUITE_SIZE, tests.size(), "the suite's filter selects: " + tests);
    long start = System.nanoTime();
    Map<String, JcstressRun.Verdict> verdicts =
        JcstressRun.run(SUITE, mode(), Path.of("jcstress-report"));
    long seconds = (System.nanoTime() - start) / 1_000_000_000L;
    verdicts.values().forEach(v -> System.out.println("jcstress " + v));
    System.out.println("jcstress " + mode() + " mode: " + verdicts.size() + " tests in " + seconds
        + " s");
    assertEquals(tests, new java.util.TreeSet<>(verdicts.keySet()),
        "every selected test reported results");
    List<String> failed =
        verdicts.values().stream()
            .filter(v -> !v.ok())
            .map(v -> v.test() + " " + v.status() + " " + v.counts() + " " + v.failures())
            .collect(Collectors.toList());
    assertTrue(failed.isEmpty(), "jcstress failures:\n" + String.join("\n", failed));
  }

  @Test
  void aRacyToyIsReportedForbidden() throws Exception {
    Map<String, JcstressRun.Verdict> verdicts =
        JcstressRun.run(TOY, "sanity", Path.of("jcstress-report-selfcheck"));
    JcstressRun.Verdict toy = verdicts.get("dev.prime.selfcheck.UnlockedClaimToy");
    System.out.println("jcstress self-check " + toy);
    assertTrue(toy != null && toy.samples() > 0, "the toy ran: " + verdicts);
    assertFalse(toy.passed(), "the duplicate claim was caught: " + toy.counts());
    long duplicates =
        toy.counts().getOrDefault("0, 0 (FORBIDDEN)", 0L)
            + toy.counts().getOrDefault("1, 1 (FORBIDDEN)", 0L);
    assertTrue(duplicates > 0, "duplicate claims counted as FORBIDDEN: " + toy.counts());
  }
}
