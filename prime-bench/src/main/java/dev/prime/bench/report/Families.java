package dev.prime.bench.report;

import dev.prime.bench.AsyncChainBenchmark;
import dev.prime.bench.AsyncHandOffBenchmark;
import dev.prime.bench.OptimusBenchmark;
import dev.prime.bench.RecordingOverheadBenchmark;
import dev.prime.bench.SyncChainBenchmark;
import dev.prime.bench.SyncPeerBenchmark;
import dev.prime.bench.SyncSourceBenchmark;
import java.util.List;

/**
 * Every benchmark family of the suite, in table order. To add a family, write its benchmark class
 * and add one line here: the runner, the smoke test, the Markdown tables and the charts pick it
 * up. A family with a new {@code table} title gets a table (and chart) of its own.
 */
public final class Families {
  /** The synchronous table's title. */
  public static final String SYNC = "Synchronous mode";

  /** The asynchronous table's title. */
  public static final String ASYNC = "Asynchronous mode";

  /** The Optimus table's title: one synchronous call through a linked chain, against raw Jedis. */
  public static final String OPTIMUS = "Optimus against a raw Jedis echo loop, same Redis (per call)";

  /**
   * The recording table's title: the synchronous rows with the core's recording off (the default)
   * and on (issue 11).
   */
  public static final String RECORDING = "Recording off and on (synchronous, monomorphic)";

  private static final List<String> RECORDING_SCENARIOS = List.of("recordingOff", "recordingOn");
  private static final List<String> HOPS = List.of("1hop", "4hops");
  private static final List<String> BOTH = List.of("monomorphic", "polluted");
  private static final List<String> MONO = List.of("monomorphic");

  /** The suite. */
  public static final List<Family> ALL =
      List.of(
          new Family(SYNC, "FOR", SyncChainBenchmark.class, "forHandWritten", true, BOTH),
          new Family(SYNC, "Radiant chains", SyncChainBenchmark.class, "radiant", false, BOTH),
          new Family(SYNC, "Liberty chains", SyncChainBenchmark.class, "liberty", false, BOTH),
          new Family(SYNC, "Prime sources + collector", SyncSourceBenchmark.class, "primeSource",
              false, BOTH),
          new Family(SYNC, "Kotlin Flow", SyncPeerBenchmark.class, "kotlinFlow", false, BOTH),
          new Family(SYNC, "Project Reactor", SyncPeerBenchmark.class, "reactor", false, BOTH),
          new Family(ASYNC, "FOR", AsyncChainBenchmark.class, "forHandWritten", true, MONO),
          new Family(ASYNC, "Radiant chains", AsyncChainBenchmark.class, "radiant", false, MONO),
          new Family(ASYNC, "Liberty chains", AsyncChainBenchmark.class, "liberty", false, MONO),
          new Family(ASYNC, "Prime sources (Liberty chain linked)", AsyncHandOffBenchmark.class,
              "primeSource", false, MONO),
          new Family(ASYNC, "Kotlin Channels", AsyncHandOffBenchmark.class, "kotlinChannel", false,
              MONO),
          new Family(ASYNC, "Reactor publishOn", AsyncHandOffBenchmark.class, "reactorPublishOn",
              false, MONO),
          new Family(ASYNC, "LMAX Disruptor", AsyncHandOffBenchmark.class, "disruptor", false,
              MONO),
          new Family(OPTIMUS, "raw Jedis echo loop", OptimusBenchmark.class, "rawCall", true, HOPS),
          new Family(OPTIMUS, "Optimus linked chain", OptimusBenchmark.class, "optimusCall", false,
              HOPS),
          new Family(RECORDING, "FOR", RecordingOverheadBenchmark.class, "forHandWritten", true,
              RECORDING_SCENARIOS),
          new Family(RECORDING, "Radiant chains", RecordingOverheadBenchmark.class, "radiant",
              false, RECORDING_SCENARIOS),
          new Family(RECORDING, "Liberty chains", RecordingOverheadBenchmark.class, "liberty",
              false, RECORDING_SCENARIOS),
          new Family(RECORDING, "Prime sources + collector", RecordingOverheadBenchmark.class,
              "primeSource", false, RECORDING_SCENARIOS));

  private Families() {}
}
