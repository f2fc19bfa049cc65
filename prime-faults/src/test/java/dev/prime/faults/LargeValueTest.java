package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.optimus.DeadLetter;
import dev.prime.optimus.KryoCodec;
import dev.prime.optimus.OptimusCore;
import dev.prime.optimus.ValueTooLargeException;
import java.util.List;
import java.util.Map;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;
import redis.clients.jedis.Jedis;

/**
 * Issue 9 item 6: a backlog of large values (2 MiB each, far more in total than the worker's
 * heap) waits for a worker JVM started with {@code -Xmx128m}; it processes them all, in order,
 * without an {@link OutOfMemoryError}. An entry above the size limit found in Redis is
 * dead-lettered (keeping a bounded prefix, not the blob); a value above the limit is refused at
 * publish and at call time with {@code ValueTooLargeException}, at once.
 */
class LargeValueTest {
  private static final int MIB = 1024 * 1024;
  /** Above the default {@code maxValueBytes} of 16 MiB. */
  private static final int OVERSIZE = 17 * MIB;

  @Test
  void aBacklogOfLargeValuesIsProcessedInASmallHeapAndOversizeValuesAreRefused() throws Exception {
    int count = FaultMode.current().largeValues;
    String name = "large";
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<byte[]> blobs = new EventBlock<>();
    Ledger ledger = new Ledger(0, count);
    sink.set(ledger);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        OptimusCore core = Cores.core(redis.url(), name, StreamTopology.WIDE_RETENTION);
        Jedis raw = redis.client()) {
      var large = StreamTopology.declareLarge(core, blobs, true);
      Block<byte[], Integer> size = large.size();
      core.start();
      LedgerFeed.start(large.observer(), sink, name);
      for (int i = 0; i < count / 2; i++) blobs.publish(StreamTopology.blob(i, 2 * MIB));
      byte[] oversizeEntry = EnvelopeBytes.value(424242, KryoCodec.standard().encode(StreamTopology.blob(-1, OVERSIZE)));
      raw.rpush(TopologyKeys.bytes(new TopologyKeys(name).serviceInput("measure")), oversizeEntry);
      for (int i = count / 2; i < count; i++) blobs.publish(StreamTopology.blob(i, 2 * MIB));

      try (WorkerJvm worker = WorkerJvm.start("large-worker", List.of("-Xmx128m"), Map.of(), List.of("large", redis.url(), name))) {
        worker.awaitReady();
        long started = System.nanoTime();
        boolean all = ledger.awaitAll(FaultMode.PATIENCE);
        long took = System.nanoTime() - started;
        long outOfMemory = worker.linesContaining("OutOfMemoryError");
        String publishOutcome = outcome(() -> blobs.publish(StreamTopology.blob(-2, OVERSIZE)));
        String callOutcome = outcome(() -> size.process(StreamTopology.blob(-3, OVERSIZE)));
        Bounded.await(java.time.Duration.ofSeconds(10), () -> !core.deadLetters("measure").isEmpty());
        List<DeadLetter> letters = core.deadLetters("measure");
        long keptBytes = letters.stream().mapToLong(l -> l.bytes().length).max().orElse(0);
        Figures.report("large values: " + count + " x 2 MiB backlog, worker -Xmx128m: " + ledger.counts() + " in "
            + Figures.seconds(took) + ", " + outOfMemory + " OutOfMemoryError; a " + OVERSIZE / MIB
            + " MiB entry in Redis: " + letters.size() + " dead letter(s) keeping " + keptBytes + " bytes; a "
            + OVERSIZE / MIB + " MiB publish " + publishOutcome + "; a " + OVERSIZE / MIB + " MiB call " + callOutcome);
        assertTrue(all, "every large value is processed: " + ledger.counts() + "\nworker output:\n" + worker.output());
        assertEquals(0, outOfMemory, worker.output());
        assertEquals(0, ledger.duplicated(), ledger.counts());
        assertEquals(0, ledger.reordered(), ledger.counts());
        assertTrue(publishOutcome.startsWith("refused with ValueTooLargeException"), "publish: " + publishOutcome);
        assertTrue(callOutcome.startsWith("refused with ValueTooLargeException"), "call: " + callOutcome);
        assertEquals(1, letters.size(), "the oversize entry found in Redis is dead-lettered: " + letters);
        assertTrue(keptBytes < OVERSIZE / 4, "a dead letter keeps a bounded prefix, not the blob: " + keptBytes + " bytes");
      }
    }
  }

  /** What happened to an operation: "refused with X in 0.01 s" or "accepted in ...". */
  private static String outcome(Runnable operation) {
    long started = System.nanoTime();
    try {
      operation.run();
      return "accepted in " + Figures.seconds(System.nanoTime() - started);
    } catch (RuntimeException e) {
      String kind = e instanceof ValueTooLargeException ? "ValueTooLargeException" : e.getClass().getName();
      return "refused with " + kind + " in " + Figures.seconds(System.nanoTime() - started) + " (" + e.getMessage() + ")";
    }
  }
}
