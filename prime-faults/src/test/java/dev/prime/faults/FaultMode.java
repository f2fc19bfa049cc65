package dev.prime.faults;

import java.time.Duration;
import java.util.Locale;

/**
 * How hard the suite pushes: {@code short} (the default, run by {@code ./mvnw -B verify}, about
 * four and a half minutes on two cores) or {@code long} ({@code -Dprime.faults=long}: more runs,
 * more values, longer outages). Every figure a test uses comes from here, so the two modes differ in one place.
 */
enum FaultMode {
  SHORT(2, 2_000, Duration.ZERO, 1, 5_000, 8, 120, 500, 200),
  LONG(6, 10_000, Duration.ofSeconds(3), 3, 20_000, 50, 300, 2_000, 5_000);

  /** Runs of each kill signal against a worker JVM. */
  final int killRuns;
  /** Ids sent per worker-kill run. */
  final int idsPerRun;
  /** How long redis-server stays down before it is restarted. */
  final Duration redisOutage;
  /** Kill-and-restart runs of redis-server. */
  final int redisRuns;
  /** Ids published while the service's host is down (more than the default retention of 1024). */
  final int backlog;
  /** Calls whose connection is cut right after the request was written. */
  final int cutCalls;
  /** Values of 2 MiB waiting for a worker with a small heap. */
  final int largeValues;
  /** Readers left behind by a killed process. */
  final int deadReaders;
  /** Random byte strings pushed into a service's input on top of the named hostile kinds. */
  final int randomHostile;

  FaultMode(int killRuns, int idsPerRun, Duration redisOutage, int redisRuns, int backlog, int cutCalls,
      int largeValues, int deadReaders, int randomHostile) {
    this.killRuns = killRuns;
    this.idsPerRun = idsPerRun;
    this.redisOutage = redisOutage;
    this.redisRuns = redisRuns;
    this.backlog = backlog;
    this.cutCalls = cutCalls;
    this.largeValues = largeValues;
    this.deadReaders = deadReaders;
    this.randomHostile = randomHostile;
  }

  /** The mode chosen by the system property {@code prime.faults} ({@code short} if unset). */
  static FaultMode current() {
    String chosen = System.getProperty("prime.faults", "short").trim().toLowerCase(Locale.ROOT);
    switch (chosen) {
      case "":
      case "short":
        return SHORT;
      case "long":
        return LONG;
      default:
        throw new IllegalArgumentException(
            "-Dprime.faults=" + chosen + " is not a fault mode; use short (the default) or long");
    }
  }

  /** How long a test waits for something that should happen within seconds, before failing. */
  static final Duration PATIENCE = Duration.ofSeconds(60);
}
