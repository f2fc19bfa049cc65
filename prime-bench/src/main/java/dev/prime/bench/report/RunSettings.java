package dev.prime.bench.report;

import java.util.List;

/**
 * How long and how often the suite measures.
 *
 * @param name the mode's name, as given on the command line
 * @param forks forks per (benchmark, parameters) pair, at least 1
 * @param warmupIterations warm-up iterations per fork
 * @param warmupMillis length of a warm-up iteration
 * @param iterations measured iterations per fork
 * @param iterationMillis length of a measured iteration
 * @param payloads payload sizes in bytes
 * @param allScenarios whether each family runs in all its scenarios, or only its first
 * @param allocation whether to attach JMH's GC profiler (allocation per transmission)
 */
public record RunSettings(
    String name,
    int forks,
    int warmupIterations,
    int warmupMillis,
    int iterations,
    int iterationMillis,
    List<String> payloads,
    boolean allScenarios,
    boolean allocation) {

  private static final List<String> TABLE1_PAYLOADS = List.of("100", "1024", "10240");

  /**
   * About 8 minutes on 2 cores: 1 fork, 3 × 0.5 s warm-up, 5 × 1 s measured (five iterations,
   * so the 99.9 % error is not blown up by Student's t for two degrees of freedom).
   */
  public static final RunSettings QUICK =
      new RunSettings("quick", 1, 3, 500, 5, 1000, TABLE1_PAYLOADS, true, true);

  /** About 25 minutes on 2 cores: 2 forks, 5 × 1 s warm-up, 5 × 1 s measured. */
  public static final RunSettings FULL =
      new RunSettings("full", 2, 5, 1000, 5, 1000, TABLE1_PAYLOADS, true, true);

  /** CI's smoke run: every family once, 100 B, first scenario, one 100 ms iteration. */
  public static final RunSettings SMOKE =
      new RunSettings("smoke", 1, 0, 100, 1, 100, List.of("100"), false, false);

  /** Checks the fields. */
  public RunSettings {
    if (forks < 1) {
      throw new IllegalArgumentException(
          "forks must be at least 1 (a benchmark in the runner's JVM is not isolated), was "
              + forks);
    }
    payloads = List.copyOf(payloads);
  }

  /**
   * The settings for a mode's name.
   *
   * @param name quick, full or smoke
   * @return the settings
   * @throws IllegalArgumentException for another name
   */
  public static RunSettings named(String name) {
    return switch (name) {
      case "quick" -> QUICK;
      case "full" -> FULL;
      case "smoke" -> SMOKE;
      default -> throw new IllegalArgumentException(
          "mode must be quick, full or smoke, not '" + name + "'");
    };
  }
}
