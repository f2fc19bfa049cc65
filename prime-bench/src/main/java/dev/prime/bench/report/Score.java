package dev.prime.bench.report;

import com.google.gson.JsonArray;
import com.google.gson.JsonElement;
import com.google.gson.JsonObject;
import com.google.gson.JsonParser;
import java.io.IOException;
import java.io.Reader;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;

/**
 * One result of JMH's JSON in either mode, with each fork's mean: what the throughput targets
 * compare (a time per operation or operations per second, unlike {@link Measurement}, which reads
 * times only).
 *
 * @param benchmark JMH's name of the benchmark (class name, dot, method)
 * @param params the JMH parameters
 * @param value the mean, in {@code nanoseconds per operation} for a time, or {@code operations
 *     per second} for a throughput
 * @param error the 99.9 % error of the mean in the same unit ({@code NaN} if one iteration)
 * @param throughput whether {@code value} is operations per second (else nanoseconds per operation)
 * @param forkMeans each fork's mean, in the same unit, in fork order
 * @param bytesPerOp allocation per operation ({@code gc.alloc.rate.norm}), {@code NaN} if not
 *     profiled
 */
public record Score(
    String benchmark,
    Map<String, String> params,
    double value,
    double error,
    boolean throughput,
    List<Double> forkMeans,
    double bytesPerOp) {

  /** Copies the collections. */
  public Score {
    params = Map.copyOf(params);
    forkMeans = List.copyOf(forkMeans);
  }

  /**
   * Whether this is the result of {@code method} of a benchmark class with these parameters.
   *
   * @param method the benchmark's simple name, {@code Class.method}
   * @param wanted parameters that must have these values (others may have any)
   * @return whether it matches
   */
  public boolean is(String method, Map<String, String> wanted) {
    if (!benchmark.endsWith("." + method)) {
      return false;
    }
    for (var entry : wanted.entrySet()) {
      if (!entry.getValue().equals(params.get(entry.getKey()))) {
        return false;
      }
    }
    return true;
  }

  /**
   * Reads every result of a JMH JSON file.
   *
   * @param file JMH's JSON ({@code -rf json}), annotated or not
   * @return the results, in file order
   * @throws IOException if the file cannot be read
   * @throws IllegalArgumentException if it is not JMH's JSON or a unit is unknown
   */
  public static List<Score> readAll(Path file) throws IOException {
    JsonElement json;
    try (Reader in = Files.newBufferedReader(file, StandardCharsets.UTF_8)) {
      json = JsonParser.parseReader(in);
    }
    if (!json.isJsonArray()) {
      throw new IllegalArgumentException(file + " is not JMH's JSON: the top level must be an array");
    }
    List<Score> scores = new ArrayList<>();
    for (JsonElement element : json.getAsJsonArray()) {
      scores.add(parse(element.getAsJsonObject()));
    }
    return scores;
  }

  private static Score parse(JsonObject result) {
    Map<String, String> params = new LinkedHashMap<>();
    if (result.has("params")) {
      for (var param : result.getAsJsonObject("params").entrySet()) {
        params.put(param.getKey(), param.getValue().getAsString());
      }
    }
    JsonObject primary = result.getAsJsonObject("primaryMetric");
    String unit = primary.get("scoreUnit").getAsString();
    boolean throughput = unit.startsWith("ops/");
    double scale = throughput ? opsPerSecondPer(unit) : nanosPer(unit);
    List<Double> forkMeans = new ArrayList<>();
    if (primary.has("rawData")) {
      for (JsonElement fork : primary.getAsJsonArray("rawData")) {
        JsonArray iterations = fork.getAsJsonArray();
        double sum = 0;
        for (JsonElement iteration : iterations) {
          sum += number(iteration);
        }
        forkMeans.add(iterations.isEmpty() ? Double.NaN : sum / iterations.size() * scale);
      }
    }
    double bytes = Double.NaN;
    JsonObject secondary = result.getAsJsonObject("secondaryMetrics");
    if (secondary != null && secondary.has("gc.alloc.rate.norm")) {
      bytes = number(secondary.getAsJsonObject("gc.alloc.rate.norm").get("score"));
    }
    return new Score(
        result.get("benchmark").getAsString(),
        params,
        number(primary.get("score")) * scale,
        number(primary.get("scoreError")) * scale,
        throughput,
        forkMeans,
        bytes);
  }

  /** JMH writes NaN as the string "NaN". */
  private static double number(JsonElement value) {
    return value == null || value.isJsonNull() ? Double.NaN : Double.parseDouble(value.getAsString());
  }

  private static double nanosPer(String unit) {
    return switch (unit) {
      case "ns/op" -> 1;
      case "us/op" -> 1e3;
      case "ms/op" -> 1e6;
      case "s/op" -> 1e9;
      default -> throw new IllegalArgumentException("unknown JMH unit " + unit);
    };
  }

  private static double opsPerSecondPer(String unit) {
    return switch (unit) {
      case "ops/s" -> 1;
      case "ops/ms" -> 1e3;
      case "ops/us" -> 1e6;
      case "ops/ns" -> 1e9;
      default -> throw new IllegalArgumentException("unknown JMH unit " + unit);
    };
  }
}
