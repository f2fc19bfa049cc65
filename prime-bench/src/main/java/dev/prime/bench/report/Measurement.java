package dev.prime.bench.report;

import java.util.Map;

/**
 * One result of the suite's JSON, in the table's units.
 *
 * @param benchmark JMH's name of the benchmark (class name, dot, method)
 * @param params the JMH parameters ({@code payload}, {@code scenario}, ...)
 * @param micros mean time per transmission, microseconds
 * @param errorMicros the 99.9 % error of the mean, microseconds ({@code NaN} if one iteration)
 * @param bytes allocation per transmission ({@code gc.alloc.rate.norm}), {@code NaN} if not
 *     profiled
 */
public record Measurement(
    String benchmark, Map<String, String> params, double micros, double errorMicros,
    double bytes) {

  /** Copies the parameters. */
  public Measurement {
    params = Map.copyOf(params);
  }

  /**
   * A parameter's value.
   *
   * @param name the parameter
   * @param otherwise the value if the benchmark has no such parameter
   * @return the value
   */
  public String param(String name, String otherwise) {
    return params.getOrDefault(name, otherwise);
  }
}
