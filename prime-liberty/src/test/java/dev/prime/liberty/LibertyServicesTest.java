package dev.prime.liberty;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import java.time.Duration;
import java.util.HashSet;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.Set;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * Liberty's services: every chain linked to a source, every filter, flat-map and listener runs on
 * a service thread of its own (named after its core), never on the publisher's thread, and chains
 * linked before they are linked to a source run as one service on one thread.
 */
class LibertyServicesTest {
  private static final Duration PATIENCE = Duration.ofSeconds(20);

  @Test
  void eachServiceRunsOnAThreadOfItsOwnAndLinkedChainsShareOne() throws Exception {
    Map<String, String> threads = new ConcurrentHashMap<>();
    CountDownLatch listened = new CountDownLatch(1);
    try (LibertyCore core = new LibertyCore(CoreConfig.builder().name("threads").build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      Source<Integer> scaled =
          numbers.then(
              core.chain("scale", (Integer x) -> seen(threads, "scale", x * 10))
                  .then(core.chain("shift", (Integer x) -> seen(threads, "shift", x + 1))));
      Source<Integer> positive = numbers.filter(x -> seen(threads, "filter", x) > 0);
      Source<Integer> twice = numbers.flatMap(x -> seen(threads, "flatMap", List.of(x, x)));
      numbers.listen(
          x -> {
            seen(threads, "listen", x);
            listened.countDown();
          });
      Reader<Integer> scaledReader = scaled.reader();
      Reader<Integer> positiveReader = positive.reader();
      Reader<Integer> twiceReader = twice.reader();
      core.start();

      events.publish(4);
      assertEquals(Optional.of(41), scaledReader.take(PATIENCE));
      assertEquals(Optional.of(4), positiveReader.take(PATIENCE));
      assertEquals(Optional.of(4), twiceReader.take(PATIENCE));
      assertTrue(listened.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS), "the listener ran");

      assertEquals(
          threads.get("scale"), threads.get("shift"), "linked chains run as one service: " + threads);
      Set<String> serviceThreads =
          new HashSet<>(
              List.of(
                  threads.get("scale"),
                  threads.get("filter"),
                  threads.get("flatMap"),
                  threads.get("listen")));
      assertEquals(4, serviceThreads.size(), "a thread per service: " + threads);
      for (String thread : serviceThreads) {
        assertTrue(thread.startsWith("prime-threads-"), "a thread of the core: " + thread);
        assertNotEquals(Thread.currentThread().getName(), thread, "not the publisher's thread");
      }
      assertEquals(
          serviceThreads,
          new HashSet<>(threadsOf("prime-threads-")),
          "the core's live threads are its four services");
    }
  }

  /** Records the thread that ran {@code role} and passes {@code value} on. */
  private static <T> T seen(Map<String, String> threads, String role, T value) {
    threads.put(role, Thread.currentThread().getName());
    return value;
  }

  private static List<String> threadsOf(String prefix) {
    return Thread.getAllStackTraces().keySet().stream()
        .filter(t -> t.isAlive() && t.getName().startsWith(prefix))
        .map(Thread::getName)
        .toList();
  }
}
