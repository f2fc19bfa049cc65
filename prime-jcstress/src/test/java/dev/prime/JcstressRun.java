package dev.prime;

import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Collection;
import java.util.List;
import java.util.Map;
import java.util.SortedSet;
import java.util.TreeMap;
import org.openjdk.jcstress.JCStress;
import org.openjdk.jcstress.Options;
import org.openjdk.jcstress.infra.Status;
import org.openjdk.jcstress.infra.collectors.DiskReadCollector;
import org.openjdk.jcstress.infra.collectors.InProcessCollector;
import org.openjdk.jcstress.infra.collectors.TestResult;
import org.openjdk.jcstress.infra.grading.GradingResult;
import org.openjdk.jcstress.infra.grading.TestGrading;

/**
 * One run of jcstress inside this JVM (it forks the test JVMs itself), read back from its result
 * file into a verdict per test. jcstress's own report says a run failed only by throwing after it
 * printed; this reads the results instead, so a test that did not run at all (no CPUs to schedule
 * it, no matching name) fails too, and the observed outcomes can be printed and asserted on.
 */
final class JcstressRun {
  /** One test's outcome: its status, whether jcstress graded it passed, and the counts seen. */
  record Verdict(String test, Status status, boolean passed, long samples, Map<String, Long> counts,
      List<String> failures) {
    /** {@return whether this test ran, ended normally and saw no forbidden or unknown outcome} */
    boolean ok() {
      return status == Status.NORMAL && passed && samples > 0;
    }
  }

  /** The jcstress tests a filter selects, from the list its annotation processor generated. */
  static SortedSet<String> tests(String filter) throws IOException {
    Options options = new Options(new String[] {"-t", filter});
    if (!options.parse()) {
      throw new IllegalArgumentException("jcstress refused the filter " + filter);
    }
    return new JCStress(options).getTests();
  }

  /**
   * Runs the tests {@code filter} selects in jcstress's {@code mode} and reads their results.
   *
   * @param filter a regular expression over test class names
   * @param mode jcstress options for the mode: {@code -m quick} and the like
   * @param report the directory for jcstress's HTML report
   * @return a verdict per test that reported results, by name
   */
  static Map<String, Verdict> run(String filter, List<String> mode, Path report) throws Exception {
    Files.createDirectories(report);
    List<String> args = new ArrayList<>(List.of("-t", filter, "-r", report.toString()));
    args.addAll(mode);
    Options options = new Options(args.toArray(String[]::new));
    if (!options.parse()) {
      throw new IllegalArgumentException("jcstress refused its options");
    }
    try {
      new JCStress(options).run();
    } catch (Exception | AssertionError failed) {
      // jcstress throws after its report when a test failed; the verdicts below say which (the
      // self-check toy always fails, so this line is expected in every run that includes it)
      System.out.println("jcstress's own report lists failed tests: " + failed);
    }
    InProcessCollector collector = new InProcessCollector();
    DiskReadCollector reader = new DiskReadCollector(options.getResultFile(), collector);
    try {
      reader.dump();
    } finally {
      reader.close();
    }
    Files.deleteIfExists(Path.of(options.getResultFile()));
    return verdicts(collector.getTestResults());
  }

  private static Map<String, Verdict> verdicts(Collection<TestResult> results) {
    Map<String, List<TestResult>> byTest = new TreeMap<>();
    for (TestResult result : results) {
      byTest.computeIfAbsent(result.getName(), k -> new ArrayList<>()).add(result);
    }
    Map<String, Verdict> verdicts = new TreeMap<>();
    byTest.forEach(
        (test, runs) -> {
          Status status = Status.NORMAL;
          boolean passed = true;
          long samples = 0;
          Map<String, Long> counts = new TreeMap<>();
          List<String> failures = new ArrayList<>();
          for (TestResult run : runs) { // one per JVM configuration and fork
            if (run.status() != Status.NORMAL) {
              status = run.status();
              failures.add(run.status() + ": " + String.join(" / ", run.getMessages()));
            }
            TestGrading grading = run.grading();
            passed &= grading.isPassed;
            failures.addAll(grading.failureMessages);
            samples += run.getTotalCount();
            for (GradingResult outcome : grading.gradingResults.values()) {
              counts.merge(outcome.id + " (" + outcome.expect + ")", outcome.count, Long::sum);
            }
          }
          verdicts.put(test, new Verdict(test, status, passed, samples, counts, failures));
        });
    return verdicts;
  }

  private JcstressRun() {}
}
