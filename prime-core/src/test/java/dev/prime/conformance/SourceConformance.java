package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import dev.prime.Reader;
import dev.prime.Source;
import java.time.Duration;
import java.util.ArrayList;
import java.util.HashSet;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.Set;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import java.util.stream.Collectors;
import java.util.stream.IntStream;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;

/** Sources and readers: broadcast, retention, late readers and the take/poll/drain contract. */
public interface SourceConformance extends ConformanceBase {

  /**
   * For a media whose sources live outside this process (Optimus: in Redis): a new, not yet
   * started core of the media built from {@code config}, whose sources {@link Outage#cut()} makes
   * unreachable (the connections stay open and silent) until {@link Outage#mend()}. {@code null},
   * the default, for a media whose sources are in this process: the kit then skips the outage
   * tests.
   */
  default Outage newCoreWithAnOutage(CoreConfig config) {
    return null;
  }

  /** A core whose sources can be cut off; {@link #close()} mends the cut and closes the core. */
  interface Outage extends AutoCloseable {
    /** {@return the core} */
    PrimeCore core();

    /** Makes the core's sources unreachable. */
    void cut();

    /** Makes them reachable again. */
    void mend();

    @Override
    void close();
  }

  /**
   * On the in-memory media every chain linked to a source, every filter, flat-map and listener
   * runs on a service thread of its own, named after its core and never the publisher's, and
   * chains linked before they are linked to a source run as one service, on one thread: the
   * core's live threads are exactly its services'.
   */
  @Test
  default void inMemoryServicesEachRunOnAThreadOfTheirOwnAndLinkedChainsShareOne()
      throws Exception {
    Assumptions.assumeTrue(
        blocksRunOnTheCallersThread(), "in-memory media: a service is a thread of this process");
    Map<String, String> threads = new ConcurrentHashMap<>();
    CountDownLatch listened = new CountDownLatch(1);
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      Source<Integer> scaled =
          numbers.then(
              core.chain("scale", (Integer x) -> ranOn(threads, "scale", x * 10))
                  .then(core.chain("shift", (Integer x) -> ranOn(threads, "shift", x + 1))));
      Source<Integer> positive = numbers.filter(x -> ranOn(threads, "filter", x) > 0);
      Source<Integer> twice = numbers.flatMap(x -> ranOn(threads, "flatMap", List.of(x, x)));
      numbers.listen(
          x -> {
            ranOn(threads, "listen", x);
            listened.countDown();
          });
      Reader<Integer> scaledReader = scaled.reader();
      Reader<Integer> positiveReader = positive.reader();
      Reader<Integer> twiceReader = twice.reader();
      core.start();

      events.publish(4);
      assertEquals(41, takeOrFail(scaledReader));
      assertEquals(4, takeOrFail(positiveReader));
      assertEquals(4, takeOrFail(twiceReader));
      assertTrue(
          listened.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the listener ran");

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
        assertTrue(
            thread.startsWith("prime-" + core.name() + "-"), "a thread of the core: " + thread);
        assertNotEquals(Thread.currentThread().getName(), thread, "not the publisher's thread");
      }
      assertEquals(
          serviceThreads,
          new HashSet<>(ConformanceBase.threadsOf(core)),
          "the core's live threads are its four services");
    }
  }

  /**
   * {@link dev.prime.Block}: "A core calls one block from one thread at a time ... when the block
   * backs exactly one service", and values leave a service in the order they entered it. Four
   * threads publish at once to one source: the blocks of two chains linked before they are linked
   * to it (one service on a media that fuses chains, two on one that keeps a service per chain), a
   * filter's predicate and a listener each run one value at a time, never two at once, and each
   * gets every value, those of each publisher in the order that publisher published them; the
   * chains' outputs leave in that order too.
   */
  @Test
  default void aServiceRunsItsBlockOnOneValueAtATimeWhateverThePublishers() throws Exception {
    int publishers = 4;
    int each = 100;
    List<String> roles = List.of("first", "second", "filter", "listen");
    Map<String, java.util.concurrent.atomic.AtomicInteger> inside = new ConcurrentHashMap<>();
    Map<String, java.util.concurrent.atomic.AtomicInteger> most = new ConcurrentHashMap<>();
    Map<String, List<Integer>> seen = new ConcurrentHashMap<>();
    for (String role : roles) {
      inside.put(role, new java.util.concurrent.atomic.AtomicInteger());
      most.put(role, new java.util.concurrent.atomic.AtomicInteger());
      seen.put(role, new CopyOnWriteArrayList<>());
    }
    CountDownLatch allHeard = new CountDownLatch(publishers * each);
    ExecutorService pool = Executors.newFixedThreadPool(publishers);
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("crowd", events);
      Reader<Integer> out =
          source
              .then(
                  core.chain("first", (Integer x) -> oneAtATime(inside, most, seen, "first", x))
                      .then(
                          core.chain(
                              "second", (Integer x) -> oneAtATime(inside, most, seen, "second", x))))
              .reader();
      Reader<Integer> passed =
          source.filter(x -> oneAtATime(inside, most, seen, "filter", x) >= 0).reader();
      source.listen(
          x -> {
            oneAtATime(inside, most, seen, "listen", x);
            allHeard.countDown();
          });
      core.start();
      CountDownLatch go = new CountDownLatch(1);
      List<Future<?>> publishing = new ArrayList<>();
      for (int p = 0; p < publishers; p++) {
        int base = p * 1_000;
        publishing.add(
            pool.submit(
                () -> {
                  go.await(patience().toMillis(), TimeUnit.MILLISECONDS);
                  for (int i = 0; i < each; i++) {
                    events.publish(base + i);
                  }
                  return null;
                }));
      }
      go.countDown();
      for (Future<?> publisher : publishing) {
        publisher.get(patience().toMillis(), TimeUnit.MILLISECONDS);
      }
      List<Integer> outputs = takeOrFail(out, publishers * each);
      takeOrFail(passed, publishers * each);
      assertTrue(
          allHeard.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the listener heard all");
      for (String role : roles) {
        assertEquals(1, most.get(role).get(), role + " ran on two values at once");
      }
      for (String role : roles) {
        assertInPublishersOrder(role, seen.get(role), publishers, each);
      }
      assertInPublishersOrder("the chains' outputs", outputs, publishers, each);
    } finally {
      pool.shutdownNow();
    }
  }

  /**
   * Runs {@code role} on {@code value}: notes how many calls of it are under way, the most ever,
   * and the value, giving other threads a chance to come in meanwhile; returns {@code value}.
   */
  private static int oneAtATime(
      Map<String, java.util.concurrent.atomic.AtomicInteger> inside,
      Map<String, java.util.concurrent.atomic.AtomicInteger> most,
      Map<String, List<Integer>> seen,
      String role,
      int value) {
    int now = inside.get(role).incrementAndGet();
    most.get(role).accumulateAndGet(now, Math::max);
    seen.get(role).add(value);
    for (int i = 0; i < 3; i++) {
      Thread.yield(); // widens the window in which a second call would overlap
    }
    inside.get(role).decrementAndGet();
    return value;
  }

  /**
   * Asserts that {@code values} are the values {@code 1000 * p + i} ({@code i} below {@code
   * each}) of {@code publishers} publishers, each once, and each publisher's in its order.
   */
  private static void assertInPublishersOrder(
      String what, List<Integer> values, int publishers, int each) {
    for (int p = 0; p < publishers; p++) {
      int base = p * 1_000;
      List<Integer> ofPublisher = values.stream().filter(v -> v / 1_000 == base / 1_000).toList();
      assertEquals(
          IntStream.range(base, base + each).boxed().toList(),
          ofPublisher,
          what + ": the values of publisher " + p + " in its order");
    }
    assertEquals(publishers * each, values.size(), what + ": every value once");
  }

  /** Records the thread that ran {@code role} and passes {@code value} on. */
  private static <T> T ranOn(Map<String, String> threads, String role, T value) {
    threads.put(role, Thread.currentThread().getName());
    return value;
  }

  @Test
  default void everyReaderSeesEveryValueInOrder() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<String> events = new EventBlock<>();
      Source<String> source = core.source("words", events);
      assertEquals("words", source.name());
      assertEquals(core, source.core());
      Reader<String> r1 = source.reader();
      Reader<String> r2 = source.reader();
      Reader<String> r3 = source.reader();
      core.start();
      List<String> words = List.of("a", "b", "c", "d");
      words.forEach(events::publish);
      assertEquals(words, takeOrFail(r1, 4));
      assertEquals(words, takeOrFail(r2, 4));
      assertEquals(words, r3.drain());
    }
  }

  @Test
  default void lateReaderSeesRetainedValues() throws InterruptedException {
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(3).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      core.start();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
      }
      Reader<Integer> late = source.reader();
      assertEquals(List.of(3, 4, 5), late.drain());
      assertEquals(0, late.missed());
      events.publish(6);
      assertEquals(6, takeOrFail(late));
    }
  }

  @Test
  default void readerThatFallsBehindCountsMissedValues() throws InterruptedException {
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(4).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      Reader<Integer> slow = source.reader();
      core.start();
      for (int i = 1; i <= 10; i++) {
        events.publish(i);
      }
      assertEquals(List.of(7, 8, 9, 10), slow.drain());
      assertEquals(6, slow.missed());
    }
  }

  @Test
  default void takeBlocksUntilAValueIsPublished() throws Exception {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.source(events).reader();
      core.start();
      CompletableFuture<Integer> taken = takeOnAnotherThread(reader);
      assertTrue(!taken.isDone(), "take() returned before any value was published");
      events.publish(7);
      assertEquals(7, taken.get(patience().toMillis(), TimeUnit.MILLISECONDS));
    }
  }

  @Test
  default void takeWithTimeoutPollAndDrain() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.source(events).reader();
      core.start();
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(20)));
      assertEquals(Optional.empty(), reader.take(Duration.ZERO));
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(-5)));
      assertEquals(Optional.empty(), reader.poll());
      assertEquals(List.of(), reader.drain());
      events.publish(1);
      events.publish(2);
      events.publish(3);
      assertEquals(Optional.of(1), reader.take(patience()));
      assertEquals(Optional.of(2), reader.poll());
      assertEquals(List.of(3), reader.drain());
      assertEquals(List.of(), reader.drain());
      assertEquals(Optional.empty(), reader.poll());
      assertThrows(NullPointerException.class, () -> reader.take(null));
    }
  }

  @Test
  default void aClosedReaderFailsEveryLaterCallAndWakesItsWaiters() throws Exception {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    assertReadersLifecycle(core, events, core.source(events));
  }

  /**
   * {@link Source#conflatedReader()} is a {@link Reader}, with the reader's lifecycle: its {@code
   * close()} wakes a {@code take()} blocked in it with {@link IllegalStateException} ("reader
   * closed"), after which every call but {@code close()} throws that, and {@code close()} is
   * idempotent; when the core closes, an open conflated reader's reads throw {@link
   * CoreClosedException}, and its {@code close()} throws nothing.
   */
  @Test
  default void aConflatedReaderHasTheReadersLifecycle() throws Exception {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    assertReadersLifecycle(
        core, events, core.source("numbers", events), Source::conflatedReader, List.of(2));
  }

  /**
   * {@link EventBlock#publish(Object)}: a {@code null} is refused with a {@link
   * NullPointerException} that says sources carry no nulls and to publish an {@code Optional} or
   * a sentinel instead.
   */
  @Test
  default void sourcesCarryNoNulls() {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source(events);
      core.start();
      NullPointerException refused =
          assertThrows(NullPointerException.class, () -> events.publish(null));
      assertTrue(
          refused.getMessage().contains("sources carry no nulls")
              && refused.getMessage().contains("Optional"),
          "says what is wrong and what to publish instead: " + refused.getMessage());
    }
  }

  /**
   * {@link CoreConfig.Builder#sourceRetention}: every retention of at least 1 is accepted; the
   * in-memory media keep it in a ring that each source allocates when it is declared, so there a
   * retention the heap cannot hold ({@code Integer.MAX_VALUE} slots pass any JVM's array limit)
   * makes that declaration throw {@link IllegalArgumentException} naming the setting, changing
   * nothing (the source's name stays free); a media that keeps sources outside the process carries
   * values as with any retention. Never an {@link Error}.
   */
  @Test
  default void theLargestRetentionWorksOrItsSourceIsRefusedClearly() throws InterruptedException {
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(Integer.MAX_VALUE).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source;
      try {
        source = core.source("kept", events);
      } catch (IllegalArgumentException refused) {
        assertTrue(
            refused.getMessage().contains("sourceRetention") && refused.getMessage().contains("kept"),
            "names the source and the setting to change: " + refused.getMessage());
        core.chain("kept", (Integer x) -> x); // the refused source's name was not claimed
        return;
      }
      Reader<Integer> plain = source.reader();
      Reader<Integer> mapped = source.then(core.chain((Integer x) -> x * 2)).reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(List.of(1, 2), takeOrFail(plain, 2));
      assertEquals(List.of(2, 4), takeOrFail(mapped, 2));
    }
  }

  @Test
  default void oneEventBlockFeedsSeveralSourcesAndCores() throws InterruptedException {
    EventBlock<Integer> events = new EventBlock<>();
    try (PrimeCore a = newCore();
        PrimeCore b = newCore()) {
      assertNotEquals(a.name(), b.name());
      Reader<Integer> ra = a.source(events).reader();
      Reader<Integer> rb = b.source(events).reader();
      a.start();
      b.start();
      events.publish(5);
      assertEquals(5, takeOrFail(ra));
      assertEquals(5, takeOrFail(rb));
    }
  }

  /**
   * A core closed without ever starting stops holding up the sources of another core that its
   * services and combinators read: the inputs they opened there close with it, as those of a
   * started core do (architecture, <i>Sources, readers and retention</i>: "a service that has
   * stopped (its core closing) no longer does"). Publishes to such a source go on past the
   * capacity of those inputs.
   */
  @Test
  default void aCoreClosedBeforeItStartedHoldsUpNoSourceOfAnotherCore()
      throws InterruptedException {
    CoreConfig small =
        CoreConfig.builder().sourceRetention(4).publishTimeout(Duration.ofMillis(200)).build();
    try (PrimeCore a = newCore(small)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> shared = a.source("shared", events);
      Reader<Integer> reader = shared.reader();
      a.start();
      PrimeCore b = newCore(small);
      b.link(shared, b.chain("never-run", (Integer x) -> x));
      b.merge(shared);
      b.close();
      for (int i = 1; i <= 12; i++) {
        events.publish(i); // threw QueueFullException naming a service of b once its input was full
      }
      assertEquals(12, reader.drain().size() + reader.missed(), "every value was published");
    }
  }

  @Test
  default void filterFlatMapAndListen() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      Reader<Integer> odd = source.filter(x -> x % 2 == 1).reader();
      Reader<Integer> twice = source.flatMap(x -> List.of(x, x)).reader();
      CopyOnWriteArrayList<Integer> heard = new CopyOnWriteArrayList<>();
      CountDownLatch allHeard = new CountDownLatch(3);
      source.listen(
          x -> {
            heard.add(x);
            allHeard.countDown();
          });
      core.start();
      events.publish(1);
      events.publish(2);
      events.publish(3);
      assertEquals(List.of(1, 3), takeOrFail(odd, 2));
      assertEquals(List.of(1, 1, 2, 2, 3, 3), takeOrFail(twice, 6));
      assertTrue(allHeard.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(List.of(1, 2, 3), heard);
    }
  }

  /**
   * {@link Source#flatMap}: "all values that {@code block} makes of each value of this one, in
   * order". The values made of one value leave in the iterable's order, all before any made of
   * the next value; an empty iterable drops its value; and nothing else comes.
   */
  @Test
  default void flatMapPublishesTheValuesMadeOfEachValueInTheirOrder()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> spread =
          core.source(events)
              .flatMap(x -> x == 0 ? List.<Integer>of() : List.of(x * 10, x * 20, x * 30))
              .reader();
      core.start();
      for (int x : List.of(1, 0, 2, 3)) {
        events.publish(x);
      }
      assertEquals(List.of(10, 20, 30, 20, 40, 60, 30, 60, 90), takeOrFail(spread, 9));
      assertEquals(Optional.empty(), spread.poll(), "one value too many");
    }
  }

  /**
   * {@link Source#flatMap}: "a {@code null} element of the iterable is skipped, and a {@code null}
   * iterable drops its value as an empty one does, ... without a call of the error handler".
   */
  @Test
  default void flatMapSkipsNullElementsAndDropsANullIterable() throws InterruptedException {
    List<Throwable> failures = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder().errorHandler((service, input, error) -> failures.add(error)).build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> spread =
          core.source(events)
              .flatMap(x -> x == 0 ? null : java.util.Arrays.asList(x, null, x + 1, null))
              .reader();
      core.start();
      for (int x : List.of(1, 0, 5)) {
        events.publish(x);
      }
      assertEquals(List.of(1, 2, 5, 6), takeOrFail(spread, 4));
      assertEquals(Optional.empty(), spread.poll(), "one value too many");
      assertEquals(List.of(), failures, "nothing went to the error handler");
    }
  }

  /**
   * {@link Reader}: "concurrent calls are safe but each value goes to exactly one of the
   * callers", and a reader reads in publication order. Four threads taking from one reader, of an
   * event source and of a service's output, share the values: none is taken twice, none is lost,
   * and each thread gets its values in publication order.
   */
  @Test
  default void concurrentTakersOfOneReaderGetEachValueOnceAndInOrder() throws Exception {
    int takers = 4;
    int each = 50;
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("shared", events);
      List<Reader<Integer>> readers =
          List.of(source.reader(), source.then(core.chain("pass", (Integer x) -> x)).reader());
      core.start();
      ExecutorService pool = Executors.newFixedThreadPool(takers * readers.size());
      try {
        List<List<Future<List<Integer>>>> taken = new ArrayList<>();
        for (Reader<Integer> reader : readers) {
          List<Future<List<Integer>>> ofReader = new ArrayList<>();
          for (int t = 0; t < takers; t++) {
            ofReader.add(pool.submit(() -> takeOrFail(reader, each)));
          }
          taken.add(ofReader);
        }
        for (int i = 0; i < takers * each; i++) {
          events.publish(i);
        }
        for (int r = 0; r < readers.size(); r++) {
          List<Integer> all = new ArrayList<>();
          for (Future<List<Integer>> ofTaker : taken.get(r)) {
            List<Integer> mine = ofTaker.get(patience().toMillis() * 2, TimeUnit.MILLISECONDS);
            assertEquals(mine.stream().sorted().collect(Collectors.toList()), mine, "reader " + r);
            all.addAll(mine);
          }
          all.sort(null);
          assertEquals(
              IntStream.range(0, takers * each).boxed().collect(Collectors.toList()),
              all,
              "reader " + r + ": every value once");
          assertEquals(Optional.empty(), readers.get(r).poll(), "reader " + r + ": nothing more");
        }
      } finally {
        pool.shutdownNow();
      }
    }
  }

  /**
   * {@link Source}: a reader starts "at the oldest value the source retains", and {@link Reader}:
   * one that falls more than the retention behind loses the oldest values and counts them in
   * {@link Reader#missed()}. A source is a source whoever publishes to it: a service's output
   * keeps the same promises as an event source.
   */
  @Test
  default void aServiceOutputRetainsAndCountsMissedValuesLikeAnEventSource()
      throws InterruptedException {
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(3).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> output = core.source(events).then(core.chain("tenfold", (Integer x) -> x * 10));
      Reader<Integer> slow = output.reader();
      Reader<Integer> pacer = output.reader();
      core.start();
      for (int i = 1; i <= 6; i++) {
        events.publish(i);
        assertEquals(i * 10, takeOrFail(pacer));
      }
      Reader<Integer> late = output.reader();
      assertEquals(List.of(40, 50, 60), late.drain(), "a new reader starts at the oldest retained");
      assertEquals(0, late.missed());
      assertEquals(List.of(40, 50, 60), slow.drain(), "a slow reader keeps the newest");
      assertEquals(3, slow.missed(), "and counts what it lost");
    }
  }

  /**
   * {@link PrimeCore} threading: "services declared after {@link PrimeCore#start()} start at
   * once". A chain, a filter, a flat-map and a listener declared on a started core process every
   * value published after their declaration; a flat-map that returns an empty iterable drops the
   * value ({@link Source#flatMap}).
   */
  @Test
  default void servicesDeclaredAfterStartRunAtOnce() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("started-first", events);
      core.start();
      Reader<Integer> linked = source.then(core.chain("plus-one", (Integer x) -> x + 1)).reader();
      Reader<Integer> even = source.filter(x -> x % 2 == 0).reader();
      Reader<Integer> evenTwice =
          source.flatMap(x -> x % 2 == 0 ? List.of(x, x) : List.<Integer>of()).reader();
      CopyOnWriteArrayList<Integer> heard = new CopyOnWriteArrayList<>();
      CountDownLatch allHeard = new CountDownLatch(4);
      source.listen(
          x -> {
            heard.add(x);
            allHeard.countDown();
          });
      for (int i = 1; i <= 4; i++) {
        events.publish(i);
      }
      assertEquals(List.of(2, 3, 4, 5), takeOrFail(linked, 4));
      assertEquals(List.of(2, 4), takeOrFail(even, 2));
      assertEquals(List.of(2, 2, 4, 4), takeOrFail(evenTwice, 4));
      assertTrue(allHeard.await(patience().toMillis(), TimeUnit.MILLISECONDS), "heard " + heard);
      assertEquals(List.of(1, 2, 3, 4), heard);
    }
  }

  /**
   * {@link Reader}: "After {@code close()}, every call but {@code close()} throws {@link
   * IllegalStateException}", a take blocked at {@code close()} ends with it, {@code close()} "never
   * throws, also on a closed core", and after the core closes a reader that is still open throws
   * {@link CoreClosedException}, as {@link Source#reader()} does. The same promises for a reader
   * of a service's output as for one of an event source.
   */
  @Test
  default void aReaderOfAServiceOutputKeepsTheReadersLifecycle() throws Exception {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    assertReadersLifecycle(
        core, events, core.source(events).then(core.chain("kept", (Integer x) -> x)));
  }

  /**
   * Checks the {@link Reader} lifecycle on two readers of {@code source}, which {@code events}
   * feeds: a closed reader wakes its blocked take and fails every later call, the other reads on,
   * and after {@code core} closes (this closes it) the open one throws {@link
   * CoreClosedException}; {@code close()} never throws.
   */
  private void assertReadersLifecycle(PrimeCore core, EventBlock<Integer> events, Source<Integer> source)
      throws Exception {
    assertReadersLifecycle(core, events, source, Source::reader, List.of(1, 2));
  }

  /**
   * As {@link #assertReadersLifecycle(PrimeCore, EventBlock, Source)}, for the readers {@code
   * reading} opens ({@link Source#reader()}, {@link Source#conflatedReader()}): the open one reads
   * {@code theOtherReads} after the other closed.
   */
  private void assertReadersLifecycle(
      PrimeCore core,
      EventBlock<Integer> events,
      Source<Integer> source,
      java.util.function.Function<Source<Integer>, Reader<Integer>> reading,
      List<Integer> theOtherReads)
      throws Exception {
    try {
      Reader<Integer> open = reading.apply(source);
      Reader<Integer> closing = reading.apply(source);
      core.start();
      events.publish(1);
      assertEquals(1, takeOrFail(closing));
      CompletableFuture<Integer> blocked = takeOnAnotherThread(closing);
      long started = System.nanoTime();
      closing.close();
      closing.close(); // idempotent
      ExecutionException woken =
          assertThrows(
              ExecutionException.class,
              () -> blocked.get(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertTrue(
          woken.getCause() instanceof IllegalStateException
              && !(woken.getCause() instanceof CoreClosedException)
              && woken.getCause().getMessage().contains("reader closed"),
          "a take blocked at close() ends with IllegalStateException: " + woken.getCause());
      Duration wakeTook = Duration.ofNanos(System.nanoTime() - started);
      assertTrue(wakeTook.compareTo(Duration.ofSeconds(3)) < 0, "woken after " + wakeTook);
      List<Executable> calls =
          List.of(
              closing::take,
              () -> closing.take(Duration.ofMillis(10)),
              closing::poll,
              closing::drain,
              closing::missed);
      for (Executable call : calls) {
        IllegalStateException e = assertThrows(IllegalStateException.class, call);
        assertTrue(e.getMessage().contains("reader closed"), e.getMessage());
      }
      events.publish(2);
      assertEquals(theOtherReads, takeOrFail(open, theOtherReads.size()), "the other reader reads on");
      core.close();
      assertThrows(CoreClosedException.class, () -> reading.apply(source));
      List<Executable> onClosedCore =
          List.of(open::take, () -> open.take(Duration.ofMillis(10)), open::poll, open::drain);
      for (Executable call : onClosedCore) {
        assertThrows(CoreClosedException.class, call);
      }
      open.close(); // on a closed core too: no exception
      closing.close();
      ConformanceBase.assertNoThreadsLeft(core);
    } finally {
      core.close();
    }
  }

  /**
   * {@link Reader#take(Duration)}: "zero or negative means do not wait", empty "if none was
   * published in time"; {@link Reader#poll()} and {@link Reader#drain()} never block. The same on
   * a reader of a service's output as on one of an event source: each call without a value
   * returns empty at once (five of them within 3 s, far below any wait), and then the values
   * come in order.
   */
  @Test
  default void takeWithTimeoutPollAndDrainOnAServiceOutput() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader =
          core.source(events).then(core.chain("echo", (Integer x) -> x)).reader();
      core.start();
      long began = System.nanoTime();
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(20)));
      assertEquals(Optional.empty(), reader.take(Duration.ZERO));
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(-5)));
      assertEquals(Optional.empty(), reader.poll());
      assertEquals(List.of(), reader.drain());
      Duration took = Duration.ofNanos(System.nanoTime() - began);
      assertTrue(took.compareTo(Duration.ofSeconds(3)) < 0, "five empty reads took " + took);
      assertThrows(NullPointerException.class, () -> reader.take(null));
      events.publish(1);
      events.publish(2);
      events.publish(3);
      assertEquals(Optional.of(1), reader.take(patience()));
      assertEquals(List.of(2, 3), takeOrFail(reader, 2));
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(-1)));
      assertEquals(List.of(), reader.drain());
      assertEquals(Optional.empty(), reader.poll());
    }
  }

  /**
   * {@link Reader}: "When the core is closed, blocked and later calls throw {@link
   * CoreClosedException}", {@link Reader#missed()} included; before that, {@code missed()} counts
   * what the reader lost, on a reader of an event source and of a service's output alike.
   */
  @Test
  default void missedCountsWhatWasLostAndThrowsCoreClosedOnAClosedCore()
      throws InterruptedException {
    PrimeCore core = newCore(CoreConfig.builder().sourceRetention(2).build());
    Reader<Integer> direct;
    Reader<Integer> served;
    try (core) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("lossy", events);
      Source<Integer> output = source.then(core.chain("lossy-copy", (Integer x) -> x));
      direct = source.reader();
      served = output.reader();
      Reader<Integer> pacer = output.reader();
      core.start();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
        assertEquals(i, takeOrFail(pacer));
      }
      assertEquals(List.of(4, 5), direct.drain());
      assertEquals(List.of(4, 5), served.drain());
      assertEquals(3, direct.missed());
      assertEquals(3, served.missed());
    }
    assertThrows(CoreClosedException.class, direct::missed);
    assertThrows(CoreClosedException.class, served::missed);
  }

  /**
   * {@link Reader}: a reader returns each value once, in order, whichever calls it is read with.
   * A reader that mixes {@link Reader#take()}, {@link Reader#poll()} and {@link Reader#drain()}
   * goes on exactly where its previous call stopped: ten steps in which each of the three follows
   * each of the three (take after take, poll after take, drain after poll, ...), each step reading
   * a batch of three values, return every value once and in order, and afterwards the reader has
   * nothing. A take's batch is published by another thread while the reader waits; a poll's or
   * drain's batch is published first, and a second reader of the same source shows it arrived
   * before the step reads. The same on a reader of an event source and of a service's output.
   */
  @Test
  default void aReaderGoesOnWhereItsLastCallStoppedWhateverMixOfTakePollAndDrain()
      throws Exception {
    List<String> steps =
        List.of("take", "take", "poll", "take", "drain", "poll", "poll", "drain", "drain", "take");
    int batch = 3;
    ExecutorService publisher = Executors.newSingleThreadExecutor();
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> direct = core.source("mixed", events);
      Source<Integer> served = direct.then(core.chain("relay", (Integer x) -> x));
      List<Source<Integer>> sources = List.of(direct, served);
      List<Reader<Integer>> readers = List.of(direct.reader(), served.reader());
      List<Reader<Integer>> pacers = List.of(direct.reader(), served.reader());
      core.start();
      for (int step = 0; step < steps.size(); step++) {
        String mode = steps.get(step);
        List<Integer> values =
            IntStream.range(step * batch, (step + 1) * batch).boxed().toList();
        Future<?> published = null;
        if (mode.equals("take")) {
          published = publisher.submit(() -> values.forEach(events::publish));
        } else {
          values.forEach(events::publish);
        }
        for (int i = 0; i < sources.size(); i++) {
          Reader<Integer> reader = readers.get(i);
          String where = sources.get(i).name() + ", step " + step + " (" + mode + ")";
          if (!mode.equals("take")) {
            assertEquals(values, takeOrFail(pacers.get(i), batch), where + ": the pacer");
          }
          List<Integer> read = new ArrayList<>();
          switch (mode) {
            case "take" -> read.addAll(takeOrFail(reader, batch));
            case "poll" -> {
              for (int v = 0; v < batch; v++) {
                reader.poll().ifPresent(read::add);
              }
            }
            default -> read.addAll(reader.drain());
          }
          assertEquals(values, read, where);
          if (mode.equals("take")) {
            assertEquals(values, takeOrFail(pacers.get(i), batch), where + ": the pacer");
          }
        }
        if (published != null) {
          published.get(patience().toMillis(), TimeUnit.MILLISECONDS);
        }
      }
      for (int i = 0; i < sources.size(); i++) {
        assertEquals(Optional.empty(), readers.get(i).poll(), sources.get(i).name() + ": one more");
        assertEquals(List.of(), readers.get(i).drain(), sources.get(i).name() + ": one more");
      }
    } finally {
      publisher.shutdownNow();
    }
  }

  /**
   * {@link Reader#drain()}: "a new list", oldest first, which the caller may change: each call
   * returns a list of its own, also when it is empty, and changing it changes nothing the reader
   * returns later. The same for a conflated reader ({@link Source#conflatedReader()}), whose drain
   * holds at most the newest value.
   */
  @Test
  default void drainReturnsANewListThatTheCallerMayChange() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("drained", events);
      Reader<Integer> plain = source.reader();
      Reader<Integer> conflated = source.conflatedReader();
      core.start();
      for (Reader<Integer> reader : List.of(plain, conflated)) {
        List<Integer> first = reader.drain();
        List<Integer> second = reader.drain();
        assertTrue(first != second, reader + ": two drains return two lists");
        first.add(99);
        assertEquals(List.of(99), first, reader + ": the caller may change an empty drain");
        assertEquals(List.of(), second, reader + ": the other list did not change");
        assertEquals(List.of(), reader.drain(), reader + ": nor did the reader");
      }
      events.publish(1);
      events.publish(2);
      List<Integer> all = plain.drain();
      List<Integer> newest = conflated.drain();
      assertEquals(List.of(1, 2), all, "oldest first");
      assertEquals(List.of(2), newest, "the conflated reader's newest");
      all.clear();
      all.add(7);
      newest.set(0, 8);
      newest.add(9);
      events.publish(3);
      assertEquals(List.of(3), plain.drain(), "the plain reader goes on where it was");
      assertEquals(List.of(3), conflated.drain(), "the conflated reader goes on where it was");
    }
  }

  /**
   * {@link Reader#take()}: "InterruptedException if the thread is interrupted before or while
   * waiting": a take that finds a value available does not wait, so it returns the value though
   * its thread's interrupt flag is set, and the flag stays set; only with nothing to read does a
   * take with the flag set end with {@link InterruptedException}. On a reader of an event source
   * and of a service's output alike; the values come each once and in order.
   */
  @Test
  default void aTakeThatFindsAValueReturnsItThoughItsThreadIsInterrupted()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> direct = core.source("flagged", events);
      Source<Integer> served = direct.then(core.chain("flagged-copy", (Integer x) -> x));
      List<Reader<Integer>> readers = List.of(direct.reader(), served.reader());
      Reader<Integer> pacer = served.reader();
      core.start();
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 2, 3), takeOrFail(pacer, 3), "the service published all three");
      for (Reader<Integer> reader : readers) {
        List<Object> taken = new ArrayList<>();
        boolean flagAfterValues;
        Throwable onEmpty = null;
        Thread.currentThread().interrupt();
        try {
          taken.add(reader.take());
          taken.add(reader.take(patience()).orElse(null));
          taken.add(reader.take(Duration.ZERO).orElse(null));
          flagAfterValues = Thread.currentThread().isInterrupted();
          try {
            reader.take(patience());
          } catch (InterruptedException e) {
            onEmpty = e;
          }
        } catch (InterruptedException e) {
          taken.add(e);
          flagAfterValues = false;
        } finally {
          Thread.interrupted(); // the test's thread goes on uninterrupted
        }
        assertEquals(
            List.<Object>of(1, 2, 3), taken, reader + ": the values there, despite the flag");
        assertTrue(flagAfterValues, reader + ": the interrupt flag stays set");
        assertTrue(
            onEmpty instanceof InterruptedException,
            reader + ": with nothing to read, the take ends with InterruptedException: " + onEmpty);
      }
    }
  }

  /**
   * {@link Reader#take(Duration)}: "zero or negative means do not wait", which is not "return
   * empty": a take with a zero or negative timeout (down to the most negative a {@link Duration}
   * holds) returns the next value when one is there, each once and in order, and empty only when
   * none is; on a reader of an event source and of a service's output alike.
   */
  @Test
  default void aTakeThatDoesNotWaitStillReturnsTheValueThatIsThere()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> direct = core.source("at-hand", events);
      Source<Integer> served = direct.then(core.chain("at-hand-copy", (Integer x) -> x));
      List<Reader<Integer>> readers = List.of(direct.reader(), served.reader());
      Reader<Integer> pacer = served.reader();
      core.start();
      for (int i = 1; i <= 4; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 2, 3, 4), takeOrFail(pacer, 4), "the service published all four");
      for (Reader<Integer> reader : readers) {
        assertEquals(Optional.of(1), reader.take(Duration.ZERO), reader + ": zero");
        assertEquals(Optional.of(2), reader.take(Duration.ofMillis(-5)), reader + ": negative");
        assertEquals(
            Optional.of(3),
            reader.take(Duration.ofSeconds(Long.MIN_VALUE)),
            reader + ": the most negative");
        assertEquals(Optional.of(4), reader.take(Duration.ZERO), reader + ": zero again");
        assertEquals(Optional.empty(), reader.take(Duration.ZERO), reader + ": nothing left");
      }
    }
  }

  /**
   * {@link Source#conflatedReader()}: "Skipped values are not counted in {@link Reader#missed()},
   * which counts only what the source's retention dropped", and its {@link Reader#take()} "waits
   * for a value newer than the last one it returned and returns the newest published by then".
   * With a retention of 3, a conflated reader that five values passed returns the fifth and
   * counts two missed (the two the retention dropped, not the two it skipped); it then has
   * nothing newer, and a take waits for the next value; six more values make it miss three more.
   */
  @Test
  default void aConflatedReaderCountsOnlyWhatRetentionDroppedAndWaitsForANewerValue()
      throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(3).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("heading", events);
      Reader<Integer> latest = source.conflatedReader();
      core.start();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
      }
      assertEquals(5, latest.take(), "the newest");
      assertEquals(2, latest.missed(), "what the retention dropped, not what conflation skipped");
      assertEquals(Optional.empty(), latest.take(Duration.ofMillis(50)), "nothing newer than 5");
      assertEquals(Optional.empty(), latest.poll(), "nothing newer than 5");
      CompletableFuture<Integer> taken = takeOnAnotherThread(latest);
      events.publish(6);
      assertEquals(6, taken.get(patience().toMillis(), TimeUnit.MILLISECONDS));
      for (int i = 7; i <= 12; i++) {
        events.publish(i);
      }
      assertEquals(Optional.of(12), latest.poll(), "the newest");
      assertEquals(5, latest.missed(), "7, 8 and 9 fell out of the retention: 2 + 3");
    }
  }

  /**
   * {@link Reader}: "concurrent calls are safe but each value goes to exactly one of the
   * callers", whichever calls they make. Four threads read one reader at once, one with timed
   * takes, one with takes that do not wait, one with polls and one with drains, while the test
   * publishes: every value reaches exactly one of them, and each gets its values in publication
   * order. On a reader of an event source and of a service's output.
   */
  @Test
  default void concurrentTakePollAndDrainCallersOfOneReaderShareEachValueOnce()
      throws Exception {
    int total = 400;
    List<String> modes = List.of("take", "take-now", "poll", "drain");
    ExecutorService pool = Executors.newFixedThreadPool(modes.size() * 2);
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> direct = core.source("crowded", events);
      Source<Integer> served = direct.then(core.chain("crowded-copy", (Integer x) -> x));
      List<Reader<Integer>> readers = List.of(direct.reader(), served.reader());
      core.start();
      long deadline = System.nanoTime() + patience().toNanos();
      List<java.util.concurrent.atomic.AtomicInteger> counts = new ArrayList<>();
      List<List<Future<List<Integer>>>> callers = new ArrayList<>();
      for (Reader<Integer> reader : readers) {
        java.util.concurrent.atomic.AtomicInteger count =
            new java.util.concurrent.atomic.AtomicInteger();
        counts.add(count);
        List<Future<List<Integer>>> ofReader = new ArrayList<>();
        for (String mode : modes) {
          ofReader.add(
              pool.submit(
                  () -> {
                    List<Integer> mine = new ArrayList<>();
                    while (count.get() < total && System.nanoTime() - deadline < 0) {
                      List<Integer> got =
                          switch (mode) {
                            case "take" -> reader.take(Duration.ofMillis(5)).stream().toList();
                            case "take-now" -> reader.take(Duration.ZERO).stream().toList();
                            case "poll" -> reader.poll().stream().toList();
                            default -> reader.drain();
                          };
                      mine.addAll(got);
                      count.addAndGet(got.size());
                      if (got.isEmpty() && !mode.equals("take")) {
                        Thread.yield();
                      }
                    }
                    return mine;
                  }));
        }
        callers.add(ofReader);
      }
      for (int i = 0; i < total; i++) {
        events.publish(i);
      }
      for (int r = 0; r < readers.size(); r++) {
        List<Integer> all = new ArrayList<>();
        for (int m = 0; m < modes.size(); m++) {
          List<Integer> mine =
              callers.get(r).get(m).get(patience().toMillis() * 2, TimeUnit.MILLISECONDS);
          String who = "reader " + r + ", the " + modes.get(m) + " caller";
          assertEquals(mine.stream().sorted().toList(), mine, who + ": in publication order");
          all.addAll(mine);
        }
        all.sort(null);
        assertEquals(
            IntStream.range(0, total).boxed().toList(),
            all,
            "reader " + r + ": every value to exactly one caller");
        assertEquals(Optional.empty(), readers.get(r).poll(), "reader " + r + ": nothing more");
      }
    } finally {
      pool.shutdownNow();
    }
  }

  /**
   * {@link Reader#poll()} and {@link Reader#drain()} "never wait for a value, also while another
   * thread waits in {@link Reader#take()} of the same reader", nor does {@link Reader#missed()}:
   * with a take waiting for a value, a poll, a drain and a missed count of the same reader return
   * at once (within 5 s, far below the kit's patience), and the value published afterwards goes
   * to the take.
   */
  @Test
  default void pollAndDrainDoNotWaitForATakeOfTheSameReader() throws Exception {
    ExecutorService pool = Executors.newSingleThreadExecutor();
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.source("contended", events).reader();
      core.start();
      List<Integer> taken = new CopyOnWriteArrayList<>();
      InterruptConformance.Caller take =
          new InterruptConformance.Caller("take", () -> taken.add(reader.take()));
      InterruptConformance.Caller.awaitBlocked(List.of(take));
      long began = System.nanoTime();
      Future<List<Object>> others =
          pool.submit(() -> List.of(reader.poll(), reader.drain(), reader.missed()));
      List<Object> polledAndDrained;
      try {
        polledAndDrained = others.get(5, TimeUnit.SECONDS);
      } catch (java.util.concurrent.TimeoutException e) {
        events.publish(-1); // lets the take, and then the poll and the drain, end
        throw new AssertionError(
            "a poll, a drain or missed() waited more than 5 s for a take of the same reader", e);
      }
      Duration took = Duration.ofNanos(System.nanoTime() - began);
      assertEquals(List.of(Optional.empty(), List.of(), 0L), polledAndDrained, "took " + took);
      events.publish(1);
      assertEquals(null, take.awaitFailure(patience()), "the take ended without a failure");
      assertEquals(List.of(1), taken, "the value published afterwards went to the take");
    } finally {
      pool.shutdownNow();
    }
  }

  /**
   * {@link CoreConfig#DEFAULT_SOURCE_RETENTION}: a core of the default configuration keeps 1024
   * values of each source for a reader that has not read them: a reader that 1030 values passed
   * reads the last 1024, in order, and counts 6 missed.
   */
  @Test
  default void aDefaultCoreRetains1024ValuesForAReader() throws InterruptedException {
    int published = CoreConfig.DEFAULT_SOURCE_RETENTION + 6;
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> idle = core.source("retained", events).reader();
      core.start();
      for (int i = 0; i < published; i++) {
        events.publish(i);
      }
      assertEquals(1024, CoreConfig.defaults().sourceRetention());
      assertEquals(IntStream.range(6, published).boxed().toList(), idle.drain());
      assertEquals(6, idle.missed());
    }
  }

  /**
   * {@link Reader}, for "a source that lives outside this process" and "may be unreachable for a
   * while": "{@link Reader#take()} then waits for it to come back; {@link Reader#take(Duration)}
   * waits at most its timeout (plus about a second for a connection that does not answer) and
   * then throws the media's {@link PrimeException} ... if the source could not be reached; {@link
   * Reader#poll()} and {@link Reader#drain()} never wait for a reconnect: they throw that
   * exception at once". With the source cut off, a take(500 ms) fails with a PrimeException (not
   * {@link CoreClosedException}) within 3.5 s (its timeout, about a second, and 2 s for a busy
   * machine), a poll and a drain each within 3 s, while a take() goes on waiting; once the source
   * is reachable again that take gets the value published then. Skipped on a media whose sources
   * are in this process ({@link #newCoreWithAnOutage} returns {@code null}).
   */
  @Test
  default void whileItsSourceIsUnreachableAReaderWaitsOrFailsAsItsCallSays() throws Exception {
    Outage outage = newCoreWithAnOutage(CoreConfig.defaults());
    Assumptions.assumeTrue(outage != null, "the media's sources live in this process");
    try (outage) {
      PrimeCore core = outage.core();
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> far = core.source("far", events);
      Reader<Integer> reader = far.reader();
      Reader<Integer> patient = far.reader();
      core.start();
      events.publish(1);
      assertEquals(1, takeOrFail(reader));
      assertEquals(1, takeOrFail(patient));
      outage.cut();
      List<Integer> waitedFor = new CopyOnWriteArrayList<>();
      InterruptConformance.Caller untimed =
          new InterruptConformance.Caller("take-through-outage", () -> waitedFor.add(patient.take()));
      List<Executable> calls =
          List.of(() -> reader.take(Duration.ofMillis(500)), reader::poll, reader::drain);
      List<Duration> bounds =
          List.of(Duration.ofMillis(3_500), Duration.ofSeconds(3), Duration.ofSeconds(3));
      List<String> names = List.of("take(500 ms)", "poll()", "drain()");
      for (int i = 0; i < calls.size(); i++) {
        long began = System.nanoTime();
        PrimeException failed = assertThrows(PrimeException.class, calls.get(i), names.get(i));
        Duration took = Duration.ofNanos(System.nanoTime() - began);
        assertTrue(
            !(failed instanceof CoreClosedException),
            names.get(i) + " fails with the media's exception for an unreachable source: " + failed);
        assertTrue(
            took.compareTo(bounds.get(i)) <= 0,
            names.get(i) + " gave up after " + took + ", more than " + bounds.get(i));
      }
      assertEquals(1, untimed.ended.getCount(), "take() waits through the outage: " + untimed.thrown);
      outage.mend();
      events.publish(2);
      assertEquals(null, untimed.awaitFailure(patience()), "the take ended without a failure");
      assertEquals(List.of(2), waitedFor, "the take got the value published after the outage");
      assertEquals(2, takeOrFail(reader), "the other reader reads on");
    }
  }

  /**
   * Starts {@code reader.take()} on another thread and returns once that thread waits in it (in a
   * park or a monitor), so that what the test does next meets a blocked take: at most the kit's
   * patience for the thread to start, then at most 300 ms for it to wait (a media whose take waits
   * in a socket read stays runnable, and then the bound passes). An interrupt fails the future.
   */
  private <T> CompletableFuture<T> takeOnAnotherThread(Reader<T> reader) throws InterruptedException {
    CountDownLatch calling = new CountDownLatch(1);
    java.util.concurrent.atomic.AtomicReference<Thread> taker =
        new java.util.concurrent.atomic.AtomicReference<>();
    CompletableFuture<T> taken =
        CompletableFuture.supplyAsync(
            () -> {
              taker.set(Thread.currentThread());
              calling.countDown();
              try {
                return reader.take();
              } catch (InterruptedException e) {
                Thread.currentThread().interrupt();
                throw new IllegalStateException("interrupted", e);
              }
            });
    assertTrue(
        calling.await(patience().toMillis(), TimeUnit.MILLISECONDS),
        "the taking thread did not start");
    long deadline = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(300);
    CountDownLatch never = new CountDownLatch(1);
    while (!taken.isDone() && System.nanoTime() < deadline) {
      Thread.State state = taker.get().getState();
      if (state == Thread.State.WAITING
          || state == Thread.State.TIMED_WAITING
          || state == Thread.State.BLOCKED) {
        break;
      }
      never.await(1, TimeUnit.MILLISECONDS); // a bounded pause between two looks
    }
    return taken;
  }
}
