package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.Optional;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.EnumSource;
import redis.clients.jedis.Jedis;

/**
 * Liveness leases between processes (issue 9 items 10 and 13): the readers of a worker JVM killed
 * with SIGKILL are reclaimed by a live process once its lease expired; a second host of a service
 * is refused with "already hosted by", and when the host is killed mid-stream its successor takes
 * over with nothing lost, duplicated or reordered, and no two hosts ever interleave. On every
 * {@link RedisSetup}.
 */
class LeaseTest {
  /** The default lease time is 5 s; a killed process's readers must be gone well within this. */
  private static final Duration RECLAIM_LIMIT = Duration.ofSeconds(30);

  @ParameterizedTest(name = "{0}")
  @EnumSource(RedisSetup.class)
  void aKilledProcesssReadersAreReclaimedAfterItsLease(RedisSetup setup) throws Exception {
    int count = FaultMode.current().deadReaders;
    String name = "dead-readers";
    TopologyKeys keys = new TopologyKeys(name);
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisSetup.Redis redis = setup.start();
        OptimusCore core = Cores.core(redis.url(), name, 1024);
        Jedis raw = redis.clientFor(name)) {
      Reader<Long> mine = core.source("ids", ids).reader();
      core.start();
      try (WorkerJvm worker = WorkerJvm.start("readers", "readers", redis.url(), name, Integer.toString(count))) {
        worker.awaitReady();
        ids.publish(1L);
        assertEquals(Optional.of(1L), mine.take(Duration.ofSeconds(10)));
        long before = readerLists(raw, keys);
        assertEquals(count + 1, before, "the worker's readers and this process's one are registered");
        worker.kill();
      }
      long killedAt = System.nanoTime();
      long reclaimed = Bounded.await(RECLAIM_LIMIT, () -> readerLists(raw, keys) == 1);
      long left = readerLists(raw, keys);
      long keysLeft = Leftovers.keys(raw, keys.readerLists()).size();
      ids.publish(2L);
      Optional<Long> stillReads = mine.take(Duration.ofSeconds(10));
      Figures.report("dead readers" + setup.suffix() + ": " + count + " readers of a SIGKILLed JVM, " + (left - 1) + " still registered and "
          + keysLeft + " reader lists in Redis (1 is this process's) "
          + (reclaimed < 0 ? "after " + Figures.seconds(RECLAIM_LIMIT) : "after " + Figures.seconds(reclaimed))
          + " since the kill; the live reader " + (stillReads.isPresent() ? "still reads" : "stopped reading")
          + " (" + Figures.seconds(System.nanoTime() - killedAt) + " in all)");
      assertTrue(reclaimed >= 0, (left - 1) + " readers of the killed process are still registered after " + RECLAIM_LIMIT);
      assertTrue(keysLeft <= 1, keysLeft + " reader lists left in Redis");
      assertEquals(Optional.of(2L), stillReads, "the live process's reader is untouched");
    }
  }

  @ParameterizedTest(name = "{0}")
  @EnumSource(RedisSetup.class)
  void aSecondHostIsRefusedAndAKilledHostsSuccessorLosesNothing(RedisSetup setup) throws Exception {
    FaultMode mode = FaultMode.current();
    String name = "single-host";
    int n = mode.idsPerRun;
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisSetup.Redis redis = setup.start();
        OptimusCore core = Cores.core(redis.url(), name, StreamTopology.WIDE_RETENTION)) {
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      core.start();
      LedgerFeed.start(stream.observer(), sink, name);
      StreamRun runs = new StreamRun(redis.url(), name, StreamTopology.WIDE_RETENTION, ids, sink);
      WorkerJvm host = runs.startWorker(1);
      try {
        String refusal;
        long refusedIn;
        try (WorkerJvm second = WorkerJvm.start("second-host", "stream", redis.url(), name,
            Integer.toString(StreamTopology.WIDE_RETENTION), "2")) {
          long started = System.nanoTime();
          refusal = second.awaitLine(line -> line.startsWith("READY") || line.startsWith("REFUSED"), FaultMode.PATIENCE)
              .orElse("(no answer) " + second.output());
          refusedIn = System.nanoTime() - started;
        }
        StreamRun.Outcome outcome = runs.killMidStream(host, true, 3, 0, n, 2 * n / 5, n / 3, false);
        host = outcome.successor();
        Ledger ledger = outcome.ledger();
        Figures.report("second host" + setup.suffix() + ": " + (refusal.startsWith("REFUSED") ? "refused" : "NOT refused") + " after "
            + Figures.seconds(refusedIn) + " (\"" + refusal + "\"); host SIGKILLed mid-stream: " + ledger.counts()
            + ", successor recovered in " + Figures.seconds(outcome.recoveredNanos()) + ", host switches " + ledger.tagSwitches());
        assertTrue(refusal.startsWith("REFUSED") && refusal.contains("already hosted by") && refusal.contains("stamp"), refusal);
        assertEquals(0, ledger.lost(), ledger.counts());
        assertEquals(0, ledger.duplicated(), ledger.counts());
        assertEquals(0, ledger.reordered(), ledger.counts());
        assertEquals(1, ledger.tagSwitches(), "one host, then its successor: never two at once");
      } finally {
        host.close();
      }
    }
  }

  /** Plain readers (not services) registered with source {@code ids}. */
  private static long readerLists(Jedis raw, TopologyKeys keys) {
    return raw.smembers(keys.sourceReaders("ids")).stream().filter(member -> member.contains(":rdr:")).count();
  }
}
