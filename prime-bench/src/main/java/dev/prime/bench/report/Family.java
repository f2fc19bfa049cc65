package dev.prime.bench.report;

import java.util.List;
import java.util.Objects;

/**
 * One row family of a results table: a benchmark method, the table and row it fills, and the
 * scenarios it runs in. A family in several scenarios fills one table per scenario.
 *
 * @param table the table's title, e.g. {@code Synchronous mode}
 * @param row the row's label, e.g. {@code Radiant chains}
 * @param benchmark the benchmark class
 * @param method the {@code @Benchmark} method
 * @param baseline whether every row of the table is compared with this one (one per table)
 * @param scenarios values of the {@code scenario} parameter to run, at least one
 */
public record Family(
    String table,
    String row,
    Class<?> benchmark,
    String method,
    boolean baseline,
    List<String> scenarios) {

  /** Checks the fields. */
  public Family {
    Objects.requireNonNull(table, "table");
    Objects.requireNonNull(row, "row");
    Objects.requireNonNull(benchmark, "benchmark");
    Objects.requireNonNull(method, "method");
    scenarios = List.copyOf(scenarios);
    if (scenarios.isEmpty()) {
      throw new IllegalArgumentException(
          "family '" + row + "' needs at least one scenario, e.g. monomorphic");
    }
  }

  /**
   * The name JMH gives the benchmark: class name, dot, method.
   *
   * @return the benchmark's name
   */
  public String benchmarkName() {
    return benchmark.getName() + "." + method;
  }
}
