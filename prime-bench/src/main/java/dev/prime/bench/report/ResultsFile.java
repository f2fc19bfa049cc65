package dev.prime.bench.report;

import com.google.gson.Gson;
import com.google.gson.GsonBuilder;
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
 * Reads and annotates JMH's JSON results: the array JMH writes, each result with an extra
 * {@code environment} object (JDK, CPU count, date, load), which JMH's own readers ignore.
 */
public final class ResultsFile {
  private static final Gson GSON =
      new GsonBuilder().setPrettyPrinting().serializeSpecialFloatingPointValues().create();

  private ResultsFile() {}

  /**
   * Adds {@code environment} to every result of JMH's JSON.
   *
   * @param jmhJson the JSON JMH wrote
   * @param environment where and when
   * @return the annotated JSON
   */
  public static String annotate(String jmhJson, Environment environment) {
    JsonArray results = JsonParser.parseString(jmhJson).getAsJsonArray();
    JsonElement env = GSON.toJsonTree(environment);
    for (JsonElement result : results) {
      result.getAsJsonObject().add("environment", env);
    }
    return GSON.toJson(results);
  }

  /**
   * Reads a results file.
   *
   * @param file JMH's JSON, annotated or not
   * @return the measurements, in file order
   * @throws IOException if the file cannot be read
   */
  public static List<Measurement> read(Path file) throws IOException {
    try (Reader in = Files.newBufferedReader(file, StandardCharsets.UTF_8)) {
      return parse(JsonParser.parseReader(in));
    }
  }

  /**
   * The environment recorded with the first result.
   *
   * @param file the annotated JSON
   * @return the environment, or {@code null} if the file has none
   * @throws IOException if the file cannot be read
   */
  public static Environment environment(Path file) throws IOException {
    try (Reader in = Files.newBufferedReader(file, StandardCharsets.UTF_8)) {
      JsonArray results = JsonParser.parseReader(in).getAsJsonArray();
      if (results.isEmpty() || !results.get(0).getAsJsonObject().has("environment")) {
        return null;
      }
      return GSON.fromJson(results.get(0).getAsJsonObject().get("environment"), Environment.class);
    }
  }

  private static List<Measurement> parse(JsonElement json) {
    if (!json.isJsonArray()) {
      throw new IllegalArgumentException("not JMH's JSON: the top level must be an array");
    }
    List<Measurement> measurements = new ArrayList<>();
    for (JsonElement element : json.getAsJsonArray()) {
      JsonObject result = element.getAsJsonObject();
      Map<String, String> params = new LinkedHashMap<>();
      if (result.has("params")) {
        for (var param : result.getAsJsonObject("params").entrySet()) {
          params.put(param.getKey(), param.getValue().getAsString());
        }
      }
      JsonObject primary = result.getAsJsonObject("primaryMetric");
      double perMicro = microsPer(primary.get("scoreUnit").getAsString());
      double bytes = Double.NaN;
      JsonObject secondary = result.getAsJsonObject("secondaryMetrics");
      if (secondary != null && secondary.has("gc.alloc.rate.norm")) {
        bytes = number(secondary.getAsJsonObject("gc.alloc.rate.norm").get("score"));
      }
      measurements.add(
          new Measurement(
              result.get("benchmark").getAsString(),
              params,
              number(primary.get("score")) * perMicro,
              number(primary.get("scoreError")) * perMicro,
              bytes));
    }
    return measurements;
  }

  /** JMH writes NaN as the string "NaN". */
  private static double number(JsonElement value) {
    return value == null || value.isJsonNull() ? Double.NaN : Double.parseDouble(value.getAsString());
  }

  private static double microsPer(String unit) {
    return switch (unit) {
      case "ns/op" -> 1e-3;
      case "us/op" -> 1;
      case "ms/op" -> 1e3;
      case "s/op" -> 1e6;
      default -> throw new IllegalArgumentException(
          "unit " + unit + " is not a time per operation: run the benchmarks in AverageTime mode");
    };
  }
}
