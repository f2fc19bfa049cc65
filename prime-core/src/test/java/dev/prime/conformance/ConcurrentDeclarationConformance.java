package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.topology.TopologyNode;
import java.util.ArrayList;
import java.util.HashSet;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * "Declaring is thread-safe" (architecture, <i>Lifecycle of a core</i>), and every name is made in
 * one place (<i>Names come from one place</i>): threads declaring at once get distinct names, a
 * topology with every declaration in it, and chains that each run their own block.
 */
public interface ConcurrentDeclarationConformance extends ConformanceBase {

  /**
   * Four threads each declare, at once, 25 unnamed chains, 25 filters of one shared source and 25
   * sources: every node has a name of its own, the topology holds all of them, the services are
   * the chains and filters, and each chain's block computes its own thread's and index's value.
   */
  @Test
  default void threadsDeclaringAtOnceGetDistinctNamesAndWholeTopology() throws Exception {
    int threads = 4;
    int each = 25;
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> shared = core.source("shared", events);
      List<Block<Integer, Integer>> blocks = new CopyOnWriteArrayList<>();
      List<Integer> offsets = new CopyOnWriteArrayList<>();
      List<Reader<Integer>> filtered = new CopyOnWriteArrayList<>();
      List<Throwable> failures = new CopyOnWriteArrayList<>();
      CountDownLatch go = new CountDownLatch(1);
      CountDownLatch done = new CountDownLatch(threads);
      for (int t = 0; t < threads; t++) {
        int thread = t;
        Thread declarer =
            new Thread(
                () -> {
                  try {
                    go.await();
                    for (int i = 0; i < each; i++) {
                      int offset = thread * 1000 + i;
                      var chain = core.chain((Integer x) -> x + offset);
                      synchronized (blocks) {
                        blocks.add(chain.toBlock());
                        offsets.add(offset);
                      }
                      filtered.add(shared.filter(x -> x % 2 == 0).reader());
                      core.source(new EventBlock<Integer>());
                    }
                  } catch (Throwable e) {
                    failures.add(e);
                  } finally {
                    done.countDown();
                  }
                },
                "kit-declarer-" + t);
        declarer.setDaemon(true);
        declarer.start();
      }
      go.countDown();
      assertTrue(done.await(patience().toMillis() * 3, TimeUnit.MILLISECONDS), "the declarers ended");
      assertEquals(List.of(), failures);
      List<String> names = new ArrayList<>();
      for (TopologyNode node : core.topology().nodes()) {
        if (!(node instanceof TopologyNode.ReaderNode)) {
          names.add(node.name());
        }
      }
      Set<String> distinct = new HashSet<>(names);
      assertEquals(names.size(), distinct.size(), "every name once: " + names);
      assertEquals(1 + threads * each * 3, names.size(), "every declaration is a node");
      assertEquals(threads * each * 2, core.serviceNames().size(), "the chains and the filters");
      core.start();
      for (int i = 0; i < blocks.size(); i++) {
        assertEquals(7 + offsets.get(i), blocks.get(i).process(7), "chain " + i + " runs its block");
      }
      events.publish(2);
      for (Reader<Integer> reader : filtered) {
        assertEquals(2, takeOrFail(reader));
      }
    }
  }

  /**
   * {@link PrimeCore#start()}: "A declaration under way on another thread when {@code start()} is
   * called ends first: its services start with the others". A merge of another core's source is
   * held in its declaration (the source's reader, which the merge opens, waits on a latch) while
   * {@code start()} is called on another thread; once both have ended, the merge is a service of
   * the core and merges what the other core's source publishes.
   */
  @Test
  default void aDeclarationUnderWayWhenStartIsCalledRunsOnceBothEnded() throws Exception {
    long patience = patience().toMillis();
    try (PrimeCore other = newCore();
        PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> ticks = other.source("ticks", events);
      other.start();
      CountDownLatch inside = new CountDownLatch(1);
      CountDownLatch release = new CountDownLatch(1);
      Source<Integer> held =
          new Source<>() {
            @Override
            public PrimeCore core() {
              return other;
            }

            @Override
            public String name() {
              return ticks.name();
            }

            @Override
            public Reader<Integer> reader() {
              inside.countDown();
              try {
                release.await(patience, TimeUnit.MILLISECONDS);
              } catch (InterruptedException e) {
                Thread.currentThread().interrupt();
              }
              return ticks.reader();
            }
          };
      ExecutorService threads = Executors.newFixedThreadPool(2);
      try {
        Future<Source<Integer>> declaring = threads.submit(() -> core.merge(held));
        assertTrue(inside.await(patience, TimeUnit.MILLISECONDS), "the merge's declaration is under way");
        Future<?> starting = threads.submit(core::start);
        release.countDown();
        Source<Integer> merged = declaring.get(patience, TimeUnit.MILLISECONDS);
        starting.get(patience, TimeUnit.MILLISECONDS);
        assertTrue(
            core.serviceNames().contains(merged.name()),
            "the merge is a service of the core: " + core.serviceNames());
        try (Reader<Integer> reader = merged.reader()) {
          events.publish(7);
          assertEquals(7, takeOrFail(reader), "the merge runs");
        }
      } finally {
        release.countDown();
        threads.shutdownNow();
        assertTrue(threads.awaitTermination(patience, TimeUnit.MILLISECONDS), "the threads ended");
      }
    }
  }
}
