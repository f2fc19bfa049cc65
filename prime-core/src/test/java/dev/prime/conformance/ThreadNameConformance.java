package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Repeat;
import dev.prime.Source;
import dev.prime.Tick;
import dev.prime.Token;
import dev.prime.Tuple2;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.TreeSet;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * "Threads a core creates are named {@code prime-<core name>-...}, which makes them easy to spot in
 * a thread dump" (architecture, <i>Lifecycle of a core</i>), for a core with every kind of service.
 */
public interface ThreadNameConformance extends ConformanceBase {

  /**
   * A core running a chain on a source, a filter, a flat-map, a listener, every combinator, a
   * timer, a sampler, a generic service, collectors, an isolated chain and a repeater, with each
   * called and fed: every thread that appeared while it was declared, started and used is named
   * {@code prime-<core name>-...}. (A core of the same media is made and closed first, so what a
   * media starts once per JVM is not counted.)
   */
  @Test
  default void everyThreadACoreCreatesCarriesItsName() throws InterruptedException {
    newCore().close(); // what a media starts once for all its cores
    Set<String> before = threadNames();
    Set<Thread> beforeThreads = Thread.getAllStackTraces().keySet();
    String name = "kit-threads-" + Long.toString(System.nanoTime(), 36);
    Set<String> appeared = new TreeSet<>();
    try (PrimeCore core = newCore(CoreConfig.builder().name(name).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      EventBlock<Integer> others = new EventBlock<>();
      Source<Integer> a = core.source("a", events);
      Source<Integer> b = core.source("b", others);
      Reader<Integer> doubled = a.then(core.chain("double", (Integer x) -> 2 * x)).reader();
      Reader<Integer> evens = a.filter(x -> x % 2 == 0).reader();
      Reader<Integer> twice = a.flatMap(x -> List.of(x, x)).reader();
      CountDownLatch heard = new CountDownLatch(2);
      a.listen(x -> heard.countDown());
      Reader<Tuple2<Integer, Integer>> latest = core.combineLatest(a, b).reader();
      Reader<Tuple2<Integer, Integer>> zipped = core.zip(a, b).reader();
      Reader<Integer> merged = core.merge(a, b).reader();
      Reader<Tuple2<Integer, Integer>> with = a.withLatestFrom(b).reader();
      Reader<Integer> sampled = a.sample(Duration.ofMillis(20)).reader();
      Reader<Tick> ticks = core.timer("beat", Duration.ofMillis(20)).reader();
      CountDownLatch worked = new CountDownLatch(1);
      core.service(
          "driver",
          () -> {
            worked.countDown();
            Thread.sleep(10);
          });
      Chain<Token, Integer> next = core.syncCollector(b);
      var nextBlock = next.toBlock();
      var allSince = core.asyncCollector(a).toBlock();
      var shared = core.isolate(core.chain("shared", (Integer x) -> x + 1)).newUser().toBlock();
      var repeated =
          core.repeater(
                  core.chain("round", (Integer x) -> x + 1),
                  (Integer input, Integer output, List<Void> c) ->
                      output >= 3 ? Repeat.stop(output) : Repeat.again(output))
              .toBlock();
      core.start();
      events.publish(2);
      others.publish(5);
      events.publish(4);
      assertEquals(List.of(4, 8), takeOrFail(doubled, 2));
      assertEquals(List.of(2, 4), takeOrFail(evens, 2));
      assertEquals(4, takeOrFail(twice, 4).size());
      assertTrue(heard.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the listener heard");
      takeOrFail(latest);
      takeOrFail(zipped);
      takeOrFail(merged, 3);
      with.poll(); // a's values may all come before b's first: nothing to pair is no failure
      takeOrFail(sampled);
      takeOrFail(ticks);
      assertTrue(worked.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the driver worked");
      assertEquals(5, nextBlock.process(Token.INSTANCE));
      allSince.process(Token.INSTANCE);
      assertEquals(8, shared.process(7));
      assertEquals(3, repeated.process(0));
      for (Thread thread : Thread.getAllStackTraces().keySet()) {
        if (!beforeThreads.contains(thread)
            && !before.contains(thread.getName())
            && !isFixtureThread(thread.getName())) {
          appeared.add(thread.getName());
        }
      }
    }
    List<String> unnamed =
        appeared.stream().filter(t -> !t.startsWith("prime-" + name + "-")).toList();
    assertEquals(List.of(), unnamed, "threads without the core's name, of " + appeared);
  }

  private static Set<String> threadNames() {
    Set<String> names = new TreeSet<>();
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      names.add(thread.getName());
    }
    return names;
  }
}
