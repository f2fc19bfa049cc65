package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.io.PrintWriter;
import java.io.StringWriter;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Deque;
import java.util.List;
import java.util.Map;
import java.util.Set;
import java.util.TreeMap;
import java.util.TreeSet;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import java.util.spi.ToolProvider;
import java.util.stream.Stream;
import org.junit.jupiter.api.Test;

/**
 * The package dependencies of prime-core's compiled classes, as jdeps reads them: no two Prime
 * packages depend on each other, directly or through others. The API never depends on the
 * internals that implement it ({@code dev.prime.internal}) nor on the media SPI ({@code
 * dev.prime.spi}), which depends on the API; the topology model depends on nothing else of Prime.
 */
class PackageCyclesTest {
  private static final Pattern EDGE = Pattern.compile("^\\s+(dev\\.prime\\S*)\\s+->\\s+(dev\\.prime\\S*)\\s");

  /** Package to the Prime packages its classes refer to (itself excluded). */
  private static Map<String, Set<String>> dependencies() throws IOException {
    List<String> args = new ArrayList<>(List.of("-verbose:package", "-filter:none"));
    try (Stream<Path> files = Files.walk(Path.of("target/classes"))) {
      files
          .filter(f -> f.toString().endsWith(".class"))
          .filter(f -> !f.getFileName().toString().equals("module-info.class"))
          .sorted()
          .forEach(f -> args.add(f.toString()));
    }
    ToolProvider jdeps = ToolProvider.findFirst("jdeps").orElseThrow();
    StringWriter out = new StringWriter();
    StringWriter err = new StringWriter();
    int status =
        jdeps.run(new PrintWriter(out), new PrintWriter(err), args.toArray(String[]::new));
    assertEquals(0, status, "jdeps failed: " + err);
    Map<String, Set<String>> graph = new TreeMap<>();
    for (String line : out.toString().split("\n")) {
      Matcher edge = EDGE.matcher(line);
      if (edge.find() && !edge.group(1).equals(edge.group(2))) {
        graph.computeIfAbsent(edge.group(1), k -> new TreeSet<>()).add(edge.group(2));
      }
    }
    assertTrue(graph.containsKey("dev.prime"), "jdeps saw no dependency of dev.prime:\n" + out);
    return graph;
  }

  /** A path of package dependencies from one package to another, or empty if there is none. */
  private static List<String> path(Map<String, Set<String>> graph, String from, String to) {
    Map<String, String> cameFrom = new TreeMap<>();
    Deque<String> queue = new ArrayDeque<>(List.of(from));
    cameFrom.put(from, from);
    while (!queue.isEmpty()) {
      String at = queue.poll();
      if (at.equals(to)) {
        List<String> path = new ArrayList<>();
        for (String p = to; !p.equals(from); p = cameFrom.get(p)) {
          path.add(0, p);
        }
        path.add(0, from);
        return path;
      }
      for (String next : graph.getOrDefault(at, Set.of())) {
        if (cameFrom.putIfAbsent(next, at) == null) {
          queue.add(next);
        }
      }
    }
    return List.of();
  }

  @Test
  void noCycleJoinsTheApiAndTheInternals() throws IOException {
    Map<String, Set<String>> graph = dependencies();
    List<String> there = path(graph, "dev.prime", "dev.prime.internal");
    List<String> back = path(graph, "dev.prime.internal", "dev.prime");
    assertTrue(
        there.isEmpty() || back.isEmpty(),
        "dev.prime and dev.prime.internal depend on each other: "
            + String.join(" -> ", there)
            + " and "
            + String.join(" -> ", back));
  }

  @Test
  void noPackageCycleAtAll() throws IOException {
    Map<String, Set<String>> graph = dependencies();
    List<String> cycles = new ArrayList<>();
    for (Map.Entry<String, Set<String>> from : graph.entrySet()) {
      for (String to : from.getValue()) {
        List<String> back = path(graph, to, from.getKey());
        if (!back.isEmpty()) {
          cycles.add(from.getKey() + " -> " + String.join(" -> ", back));
        }
      }
    }
    assertEquals(List.of(), cycles, "package cycles in prime-core");
  }

  @Test
  void theApiDependsOnNeitherTheSpiNorTheInternalsThroughTheSpi() throws IOException {
    Map<String, Set<String>> graph = dependencies();
    assertEquals(List.of(), path(graph, "dev.prime", "dev.prime.spi"), "dev.prime reaches the SPI");
    assertTrue(
        graph.getOrDefault("dev.prime.spi", Set.of()).contains("dev.prime"),
        "the SPI is built on the API: " + graph);
  }

  @Test
  void theTopologyModelDependsOnNothingElseOfPrime() throws IOException {
    assertEquals(Set.of(), dependencies().getOrDefault("dev.prime.topology", Set.of()));
  }
}
