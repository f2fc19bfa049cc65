package dev.prime.bench;

import dev.prime.optimus.EmbeddedRedis;
import java.lang.management.ManagementFactory;
import java.net.URI;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import redis.clients.jedis.Jedis;

/**
 * One embedded {@code redis-server} for one benchmark trial, and the profile of what the trial
 * made it do: after the trial, {@link #report} prints Redis's command counts and CPU time per
 * benchmark operation (from {@code INFO commandstats} and {@code INFO cpu}), which shows how many
 * round trips and how much server time a value costs. Next to it, the CPU time of this JVM (the
 * benchmark's own process: client, services, JMH) per value, so the two sides of a round trip can
 * be compared on a machine whose cores are shared.
 *
 * <p>Not thread-safe: the benchmark's setup and teardown use it; the connections it hands out
 * belong to their callers.
 */
final class RedisRig implements AutoCloseable {
  private final EmbeddedRedis redis = EmbeddedRedis.start();
  private double cpuAtReset;
  private long jvmCpuAtReset;

  /** The server's URL, {@code redis://127.0.0.1:port}. */
  String uri() {
    return redis.getUri();
  }

  /** A new plain Jedis connection to the server. */
  Jedis connect() {
    return new Jedis(URI.create(redis.getUri()));
  }

  /** Forgets the statistics so far: call once the measured topology is set up. */
  void resetStats() {
    try (Jedis jedis = connect()) {
      jedis.configResetStat();
      cpuAtReset = cpuSeconds(jedis);
    }
    jvmCpuAtReset = jvmCpuNanos();
  }

  /**
   * Prints, for the {@code operations} benchmark operations run since {@link #resetStats} (each
   * moving {@code valuesPerOperation} values), the calls of each Redis command per value and its
   * server time, and Redis's CPU time and this JVM's per value.
   */
  void report(String scenario, long operations, int valuesPerOperation) {
    double jvmCpuMicros = (jvmCpuNanos() - jvmCpuAtReset) / 1e3 / (Math.max(1, operations) * (double) valuesPerOperation);
    try (Jedis jedis = connect()) {
      report(jedis, cpuAtReset, String.format(Locale.ROOT, "%s (JVM CPU %.2f us/value)", scenario, jvmCpuMicros),
          operations, valuesPerOperation);
    }
  }

  /**
   * Prints the profile of {@link #report} for the server {@code jedis} is connected to (any
   * Redis: one node of a cluster, say), whose statistics were reset when its CPU time was
   * {@code cpuAtReset} ({@link #cpuSeconds}).
   */
  static void report(Jedis jedis, double cpuAtReset, String scenario, long operations, int valuesPerOperation) {
    double values = Math.max(1, operations) * (double) valuesPerOperation;
    List<String> lines = new ArrayList<>();
    double cpu = cpuSeconds(jedis) - cpuAtReset;
    for (String line : jedis.info("commandstats").split("\r?\n")) {
      if (!line.startsWith("cmdstat_")) {
        continue;
      }
      String command = line.substring("cmdstat_".length(), line.indexOf(':'));
      long calls = Long.parseLong(field(line, "calls="));
      double usecPerCall = Double.parseDouble(field(line, "usec_per_call="));
      lines.add(String.format(Locale.ROOT, "  %-10s %8.3f calls/value  %8.2f us/call  %8.3f us/value",
          command, calls / values, usecPerCall, calls * usecPerCall / values));
    }
    System.out.printf(Locale.ROOT, "%n[redis profile] %s: %d values; redis CPU %.2f us/value%n",
        scenario, (long) values, cpu * 1e6 / values);
    lines.forEach(System.out::println);
  }

  @Override
  public void close() {
    redis.close();
  }

  /** The CPU time of this JVM so far (every thread), or 0 where the platform does not tell. */
  private static long jvmCpuNanos() {
    return ManagementFactory.getOperatingSystemMXBean() instanceof com.sun.management.OperatingSystemMXBean os
        ? Math.max(0, os.getProcessCpuTime())
        : 0;
  }

  /** The server's CPU time so far (user and system), in seconds. */
  static double cpuSeconds(Jedis jedis) {
    String info = jedis.info("cpu");
    return Double.parseDouble(field(info, "used_cpu_user:")) + Double.parseDouble(field(info, "used_cpu_sys:"));
  }

  /** The value after {@code label} ({@code "name="} or {@code "name:"}) in an INFO text. */
  private static String field(String text, String label) {
    int at = text.indexOf(label);
    if (at < 0) {
      throw new IllegalStateException("no '" + label + "' in Redis INFO: " + text);
    }
    int start = at + label.length();
    int end = start;
    while (end < text.length() && ",\r\n".indexOf(text.charAt(end)) < 0) {
      end++;
    }
    return text.substring(start, end);
  }
}
