package dev.prime.bench.report;

import java.io.IOException;
import java.lang.management.ManagementFactory;
import java.nio.file.Files;
import java.nio.file.Path;
import java.time.Instant;
import java.time.temporal.ChronoUnit;

/**
 * Where and when a run took place, recorded with every result.
 *
 * @param jdk the Java runtime, e.g. {@code OpenJDK 64-Bit Server VM 17.0.15+6}
 * @param cpus the processors the JVM sees
 * @param cpuModel the processor's model, or {@code unknown}
 * @param os operating system and architecture
 * @param date when the run started, UTC
 * @param loadBefore the system's 1-minute load average when the run started (-1 if unknown)
 * @param loadAfter the 1-minute load average when it ended (-1 if unknown)
 */
public record Environment(
    String jdk,
    int cpus,
    String cpuModel,
    String os,
    String date,
    double loadBefore,
    double loadAfter) {

  /**
   * This JVM's environment, now.
   *
   * @return the environment, with {@code loadAfter} equal to {@code loadBefore}
   */
  public static Environment capture() {
    double load = ManagementFactory.getOperatingSystemMXBean().getSystemLoadAverage();
    return new Environment(
        System.getProperty("java.vm.name") + " " + System.getProperty("java.runtime.version")
            + " (" + System.getProperty("java.vendor") + ")",
        Runtime.getRuntime().availableProcessors(),
        readCpuModel(),
        System.getProperty("os.name") + " " + System.getProperty("os.version") + " "
            + System.getProperty("os.arch"),
        Instant.now().truncatedTo(ChronoUnit.SECONDS).toString(),
        load,
        load);
  }

  /**
   * This environment with the load average of now as {@code loadAfter}.
   *
   * @return the finished environment
   */
  public Environment finished() {
    return new Environment(
        jdk, cpus, cpuModel, os, date, loadBefore,
        ManagementFactory.getOperatingSystemMXBean().getSystemLoadAverage());
  }

  private static String readCpuModel() {
    Path cpuinfo = Path.of("/proc/cpuinfo");
    if (!Files.isReadable(cpuinfo)) {
      return "unknown";
    }
    try (var lines = Files.lines(cpuinfo)) {
      return lines
          .filter(line -> line.startsWith("model name"))
          .map(line -> line.substring(line.indexOf(':') + 1).trim())
          .findFirst()
          .orElse("unknown");
    } catch (IOException | RuntimeException unreadable) {
      return "unknown";
    }
  }
}
