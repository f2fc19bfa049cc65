package dev.prime.bench.report;

import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.Collection;
import java.util.List;
import java.util.regex.Pattern;
import org.openjdk.jmh.profile.GCProfiler;
import org.openjdk.jmh.results.RunResult;
import org.openjdk.jmh.results.format.ResultFormatFactory;
import org.openjdk.jmh.results.format.ResultFormatType;
import org.openjdk.jmh.runner.Runner;
import org.openjdk.jmh.runner.RunnerException;
import org.openjdk.jmh.runner.options.ChainedOptionsBuilder;
import org.openjdk.jmh.runner.options.OptionsBuilder;
import org.openjdk.jmh.runner.options.TimeValue;
import org.openjdk.jmh.runner.options.VerboseMode;

/**
 * Runs benchmark families through JMH's Runner API: one JMH run per family (so each family gets
 * exactly its scenarios), each (benchmark, parameters) pair in forks of its own, never in the
 * runner's JVM.
 */
public final class SuiteRunner {
  /** The length of the measured chain: the paper's 4 blocks. */
  public static final String LENGTH = "4";

  private SuiteRunner() {}

  /**
   * Runs families.
   *
   * @param families what to run
   * @param settings how long and how often
   * @param verbosity JMH's console output
   * @return every result, in family order
   * @throws RunnerException if a benchmark fails
   */
  public static List<RunResult> run(
      List<Family> families, RunSettings settings, VerboseMode verbosity) throws RunnerException {
    List<RunResult> results = new ArrayList<>();
    for (Family family : families) {
      results.addAll(new Runner(options(family, settings, verbosity).build()).run());
    }
    return results;
  }

  /**
   * The JMH options of one family.
   *
   * @param family the family
   * @param settings how long and how often
   * @param verbosity JMH's console output
   * @return the options, ready to build
   */
  public static ChainedOptionsBuilder options(
      Family family, RunSettings settings, VerboseMode verbosity) {
    List<String> scenarios =
        settings.allScenarios() ? family.scenarios() : family.scenarios().subList(0, 1);
    ChainedOptionsBuilder options =
        new OptionsBuilder()
            .include("^" + Pattern.quote(family.benchmarkName()) + "$")
            .forks(settings.forks())
            .warmupIterations(settings.warmupIterations())
            .warmupTime(TimeValue.milliseconds(settings.warmupMillis()))
            .measurementIterations(settings.iterations())
            .measurementTime(TimeValue.milliseconds(settings.iterationMillis()))
            .param("length", LENGTH)
            .param("payload", settings.payloads().toArray(String[]::new))
            .param("scenario", scenarios.toArray(String[]::new))
            .shouldFailOnError(true)
            .verbosity(verbosity);
    if (settings.allocation()) {
      options.addProfiler(GCProfiler.class);
    }
    return options;
  }

  /**
   * JMH's JSON of the results.
   *
   * @param results the results
   * @return the JSON array JMH writes with {@code -rf json}
   */
  public static String json(Collection<RunResult> results) {
    ByteArrayOutputStream bytes = new ByteArrayOutputStream();
    try (PrintStream out = new PrintStream(bytes, true, StandardCharsets.UTF_8)) {
      ResultFormatFactory.getInstance(ResultFormatType.JSON, out).writeOut(results);
    }
    return bytes.toString(StandardCharsets.UTF_8);
  }
}
