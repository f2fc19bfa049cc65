package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordedValue;
import dev.prime.Recording;
import dev.prime.RecordingOptions;
import dev.prime.Source;
import dev.prime.Reader;
import java.lang.ref.ReferenceQueue;
import java.lang.ref.WeakReference;
import java.time.Duration;
import java.time.Instant;
import java.util.ArrayList;
import java.util.List;
import java.util.NoSuchElementException;
import java.util.Optional;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.stream.LongStream;
import org.junit.jupiter.api.Test;

/**
 * Recording (docs/architecture.md, "Recording"): what sources publish and chains made of blocks
 * return is recorded per name with pseudoname, time stamps and gap-free sequence numbers, read back
 * with get / tryGet / getRange / getAll with or without time stamps, bounded by a ring whose losses
 * are counted; off by default, and then nothing is compiled in.
 */
public interface RecordingConformance extends ConformanceBase {

  /** A core recording with a ring of {@code capacity} values per name. */
  default PrimeCore recordingCore(int capacity) {
    return newCore(CoreConfig.builder().recording(RecordingOptions.ring(capacity)).build());
  }

  @Test
  default void recordsWhatSourcesPublishAndChainsReturn() throws Exception {
    try (PrimeCore core = recordingCore(100)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> doubled =
          core.source("numbers", events).then(core.chain("double", (Integer x) -> x * 2));
      Reader<Integer> reader = doubled.reader();
      Block<String, Integer> length = core.chain("length", String::length).toBlock();
      core.start();
      Instant before = Instant.now();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
      }
      assertEquals(List.of(2, 4, 6, 8, 10), takeOrFail(reader, 5));
      assertEquals(3, length.process("abc"));
      Instant after = Instant.now();

      Recording recording = core.recording();
      assertTrue(recording.names().containsAll(List.of("numbers", "double", "length")),
          "recorded names: " + recording.names());
      assertEquals(List.of(1, 2, 3, 4, 5), recording.getAll("numbers"));
      assertEquals(List.of(2, 4, 6, 8, 10), recording.getAll("double"));
      assertEquals(List.of(3), recording.getAll("length"));
      int latest = recording.get("numbers");
      assertEquals(5, latest);
      assertEquals(Optional.of(10), recording.tryGet("double"));
      assertEquals(List.of(2, 3), recording.getRange("numbers", 1, 3));
      assertEquals(List.of(), recording.getRange("numbers", 5, 9));

      List<RecordedValue<Integer>> stamped = recording.getAllStamped("double");
      assertEquals(5, stamped.size());
      for (int i = 0; i < 5; i++) {
        RecordedValue<Integer> entry = stamped.get(i);
        assertEquals("double", entry.service());
        assertNull(entry.pseudoname());
        assertEquals("double", entry.label());
        assertEquals(i, entry.sequence());
        assertEquals(2 * (i + 1), entry.value());
        assertFalse(entry.wallTime().isBefore(before), entry + " before " + before);
        assertFalse(entry.wallTime().isAfter(after), entry + " after " + after);
        if (i > 0) {
          assertTrue(entry.monotonicNanos() >= stamped.get(i - 1).monotonicNanos());
        }
      }
      RecordedValue<Integer> last = recording.getStamped("numbers");
      assertEquals(4, last.sequence());
      assertEquals(5, last.value());
      assertEquals(last, recording.<Integer>tryGetStamped("numbers").orElseThrow());
      List<RecordedValue<Integer>> range = recording.getRangeStamped("numbers", 3, 100);
      assertEquals(List.of(3L, 4L), range.stream().map(RecordedValue::sequence).toList());
      assertEquals(0, recording.dropped("numbers"));
      assertEquals(5, recording.recorded("numbers"));
      assertTrue(core.recording() == recording, "one recording per core");
    }
  }

  /**
   * {@link RecordedValue}: a chain's value is stamped "when the chain's block returned the value",
   * a source's "when the source's publish of it began". So the stamps follow each value through
   * the diagram: publishing one value at a time, each after the chain's output of the previous
   * one was read, the monotonic stamps of the source and of the chain linked to it interleave,
   * source value 0 no later than its chain output 0, that no later than source value 1, and so
   * on; and a recording read after the core closed still holds them all.
   */
  @Test
  default void timeStampsFollowEachValueFromItsSourceThroughItsChain() throws Exception {
    int values = 5;
    Recording recording;
    try (PrimeCore core = recordingCore(100)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader =
          core.source("ticks", events).then(core.chain("scaled", (Integer x) -> x * 2)).reader();
      core.start();
      for (int i = 0; i < values; i++) {
        events.publish(i);
        assertEquals(2 * i, takeOrFail(reader));
      }
      recording = core.recording();
    }
    List<RecordedValue<Integer>> ticks = recording.getAllStamped("ticks");
    List<RecordedValue<Integer>> scaled = recording.getAllStamped("scaled");
    assertEquals(values, ticks.size(), "source values recorded: " + ticks);
    assertEquals(values, scaled.size(), "chain outputs recorded: " + scaled);
    List<RecordedValue<Integer>> path = new ArrayList<>();
    for (int i = 0; i < values; i++) {
      assertEquals(i, ticks.get(i).value());
      assertEquals(2 * i, scaled.get(i).value());
      path.add(ticks.get(i));
      path.add(scaled.get(i));
    }
    for (int k = 1; k < path.size(); k++) {
      RecordedValue<Integer> earlier = path.get(k - 1);
      RecordedValue<Integer> later = path.get(k);
      assertTrue(
          later.monotonicNanos() - earlier.monotonicNanos() >= 0,
          later + " is stamped before " + earlier);
    }
  }

  @Test
  default void pseudonamesNameTheRecordingAndTheDrawing() throws Exception {
    try (PrimeCore core = recordingCore(10)) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Source<Integer> estimates =
          core.source("encoders", "Wheel encoders", ticks)
              .then(core.chain("odometry", "Wheel odometry", (Integer t) -> t + 1));
      Reader<Integer> reader = estimates.reader();
      core.start();
      ticks.publish(41);
      assertEquals(42, takeOrFail(reader));

      Recording recording = core.recording();
      RecordedValue<Integer> odometry = recording.getStamped("odometry");
      assertEquals("Wheel odometry", odometry.pseudoname());
      assertEquals("Wheel odometry", odometry.label());
      assertEquals("Wheel encoders", recording.<Integer>getStamped("encoders").pseudoname());
      assertEquals(Optional.of("Wheel odometry"), recording.pseudoname("odometry"));

      assertEquals(Optional.of("Wheel encoders"), core.topology().pseudoname("encoders"));
      String mermaid = core.topology().toMermaid();
      assertTrue(mermaid.contains("Wheel odometry (odometry)"), mermaid);
      assertTrue(mermaid.contains("Wheel encoders (encoders)"), mermaid);
      assertTrue(core.topology().toDot().contains("\"Wheel odometry (odometry)\""),
          core.topology().toDot());
    }
  }

  @Test
  default void anInvalidPseudonameIsRefusedAndRecordsNothing() {
    try (PrimeCore core = recordingCore(10)) {
      IllegalArgumentException e =
          assertThrows(
              IllegalArgumentException.class,
              () -> core.chain("planner", "two\nlines", (Integer x) -> x));
      assertTrue(e.getMessage().contains("pseudoname"), e.getMessage());
      assertThrows(IllegalArgumentException.class, () -> core.source("s", " ", new EventBlock<>()));
      assertEquals(List.of(), core.topology().nodes(), "a refused declaration records nothing");
      core.chain("planner", "Planner", (Integer x) -> x); // the name is still free
    }
  }

  /**
   * {@link PrimeCore#chain(String, String, Block)} and {@link PrimeCore#source(String, String,
   * EventBlock)}: a pseudoname is "1 to 120 characters, not only whitespace, no control
   * characters". One of one character and one of 120 (spaces inside, any other character) are
   * taken and name the recording; each outside the rule (empty, 121 characters, only whitespace, a
   * tab, a control character, DEL) is refused by a chain and by a source with an {@link
   * IllegalArgumentException} that says what a pseudoname may be, recording nothing.
   */
  @Test
  default void pseudonamesAreTakenUpTo120CharactersAndOthersAreRefusedWithTheRule()
      throws InterruptedException {
    String longest = "Wheel odometry \u2014 caf\u00e9 ".repeat(5) + "x".repeat(10);
    assertEquals(120, longest.length());
    try (PrimeCore core = recordingCore(10)) {
      List<String> bad =
          List.of("", "y".repeat(121), " \t ", "tab\tbed", "bell\u0007", "del\u007f");
      List<String> wrong = new java.util.ArrayList<>();
      for (String pseudoname : bad) {
        List<org.junit.jupiter.api.function.Executable> calls =
            List.of(
                () -> core.chain("planner", pseudoname, (Integer x) -> x),
                () -> core.source("encoders", pseudoname, new EventBlock<Integer>()));
        for (org.junit.jupiter.api.function.Executable call : calls) {
          try {
            call.execute();
            wrong.add("'" + pseudoname + "' was accepted");
          } catch (IllegalArgumentException e) {
            if (e.getMessage() == null || !e.getMessage().contains("1 to 120")) {
              wrong.add("'" + pseudoname + "': " + e.getMessage());
            }
          } catch (Throwable t) {
            wrong.add("'" + pseudoname + "' threw " + t);
          }
        }
      }
      assertEquals(List.of(), wrong, "each invalid pseudoname is refused with the rule");
      assertEquals(List.of(), core.topology().nodes(), "a refused declaration records nothing");
      EventBlock<Integer> ticks = new EventBlock<>();
      Reader<Integer> reader =
          core.source("encoders", "E", ticks)
              .then(core.chain("planner", longest, (Integer x) -> x + 1))
              .reader();
      core.start();
      ticks.publish(1);
      assertEquals(2, takeOrFail(reader));
      assertEquals(Optional.of(longest), core.recording().pseudoname("planner"));
      assertEquals(Optional.of("E"), core.recording().pseudoname("encoders"));
    }
  }

  /**
   * {@link Recording}: a chain made of a block records "each non-null value its block returns",
   * numbered per name: a chain whose block returns {@code null} for even inputs records only the
   * odd outputs, numbered 0, 1, ..., whether it runs linked to a source or is called through its
   * {@code toBlock()}; a {@code null} is neither recorded nor counted.
   */
  @Test
  default void aChainRecordsEachNonNullValueItsBlockReturnsAndNoNull() throws InterruptedException {
    try (PrimeCore core = recordingCore(10)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> odd =
          core.source("numbers", events)
              .then(core.chain("linked", (Integer x) -> x % 2 == 0 ? null : x))
              .reader();
      Block<Integer, Integer> called =
          core.chain("called", (Integer x) -> x % 2 == 0 ? null : x).toBlock();
      core.start();
      for (int i = 1; i <= 6; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 3, 5), takeOrFail(odd, 3));
      List<Integer> results = new ArrayList<>();
      for (int i = 1; i <= 6; i++) {
        results.add(called.process(i));
      }
      assertEquals(java.util.Arrays.asList(1, null, 3, null, 5, null), results);
      Recording recording = core.recording();
      for (String name : List.of("linked", "called")) {
        List<RecordedValue<Integer>> entries = recording.getAllStamped(name);
        assertEquals(
            List.of(1, 3, 5), entries.stream().map(RecordedValue::value).toList(), name);
        assertEquals(
            List.of(0L, 1L, 2L), entries.stream().map(RecordedValue::sequence).toList(), name);
        assertEquals(3, recording.recorded(name), name);
        assertEquals(Optional.of(5), recording.tryGet(name), name);
      }
    }
  }

  /**
   * {@link Recording#get(String, Duration)}: the timeout is "zero or positive" ({@link
   * IllegalArgumentException} for a negative one), and a wait for a first value ends with {@link
   * InterruptedException} "if the thread is interrupted while waiting"; {@link
   * Recording#getRange(String, long, long)} refuses a range that is not {@code 0 <= from <= to}.
   */
  @Test
  default void aRecordingGetHonoursInterruptionAndRefusesBadArguments() throws Exception {
    try (PrimeCore core = recordingCore(10)) {
      core.chain("idle", (Integer x) -> x);
      core.start();
      Recording recording = core.recording();
      IllegalArgumentException negative =
          assertThrows(
              IllegalArgumentException.class, () -> recording.get("idle", Duration.ofMillis(-1)));
      assertTrue(negative.getMessage().contains("zero or positive"), negative.getMessage());
      assertThrows(IllegalArgumentException.class, () -> recording.getRange("idle", -1, 0));
      CountDownLatch waiting = new CountDownLatch(1);
      CompletableFuture<Throwable> ended = new CompletableFuture<>();
      Thread getter =
          new Thread(
              () -> {
                waiting.countDown();
                try {
                  recording.get("idle", patience().multipliedBy(3));
                  ended.complete(null);
                } catch (Throwable t) {
                  ended.complete(t);
                }
              },
              "kit-recording-getter");
      getter.start();
      assertTrue(waiting.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      long began = System.nanoTime();
      getter.interrupt();
      Throwable thrown = ended.get(patience().toMillis(), TimeUnit.MILLISECONDS);
      assertTrue(thrown instanceof InterruptedException, "the interrupted get threw " + thrown);
      assertTrue(
          Duration.ofNanos(System.nanoTime() - began).compareTo(patience()) < 0,
          "ended by the interrupt, not by its timeout");
      getter.join(patience().toMillis());
      Thread.currentThread().interrupt();
      try {
        assertThrows(InterruptedException.class, () -> recording.get("idle", patience()));
      } finally {
        Thread.interrupted();
      }
    }
  }

  /**
   * {@link RecordedValue#value()}: "the value, as published or returned (not a copy)", also where
   * values are copied across services ({@link #newCoreWithCodec}): the recording of an event source
   * holds the very object published, and that of a chain made of a block the very object its block
   * returned, whether the chain runs linked to a source or is called through its {@code
   * toBlock()}.
   */
  @Test
  default void theRecordingHoldsTheVeryObjectsPublishedAndReturned() throws InterruptedException {
    List<Object> returned = java.util.Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core =
        newCoreWithCodec(
            CoreConfig.builder()
                .recording(RecordingOptions.ring(10))
                .copyValues(copyCodec())
                .build())) {
      EventBlock<ArrayList<Integer>> events = new EventBlock<>();
      Reader<ArrayList<Integer>> out =
          core.source("lists", events)
              .then(
                  core.chain(
                      "grown",
                      (ArrayList<Integer> list) -> {
                        ArrayList<Integer> grown = new ArrayList<>(list);
                        grown.add(0);
                        returned.add(grown);
                        return grown;
                      }))
              .reader();
      Block<Integer, ArrayList<Integer>> called =
          core.chain(
                  "called",
                  (Integer x) -> {
                    ArrayList<Integer> made = new ArrayList<>(List.of(x));
                    returned.add(made);
                    return made;
                  })
              .toBlock();
      core.start();
      ArrayList<Integer> published = new ArrayList<>(List.of(7));
      events.publish(published);
      assertEquals(List.of(7, 0), takeOrFail(out));
      assertEquals(List.of(3), called.process(3));
      Recording recording = core.recording();
      assertSame(published, recording.getAll("lists").get(0), "the very object published");
      assertSame(returned.get(0), recording.getAll("grown").get(0), "the very object returned");
      assertSame(returned.get(1), recording.getAll("called").get(0), "the very object returned");
    }
  }

  @Test
  default void anUnknownNameListsTheRecordedOnes() {
    try (PrimeCore core = recordingCore(10)) {
      core.source("numbers", new EventBlock<Integer>());
      core.chain("double", (Integer x) -> x * 2);
      Recording recording = core.recording();
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> recording.tryGet("nubmers"));
      assertTrue(e.getMessage().contains("'nubmers'"), e.getMessage());
      assertTrue(e.getMessage().contains("numbers") && e.getMessage().contains("double"),
          e.getMessage());
      assertThrows(IllegalArgumentException.class, () -> recording.get("nubmers"));
      assertThrows(IllegalArgumentException.class, () -> recording.getAll("nubmers"));
      assertThrows(IllegalArgumentException.class, () -> recording.getRange("nubmers", 0, 1));
      assertThrows(IllegalArgumentException.class, () -> recording.getRange("numbers", 2, 1));
    }
  }

  @Test
  default void recordingOffSaysHowToTurnItOn() {
    try (PrimeCore core = newCore()) {
      core.chain("double", (Integer x) -> x * 2);
      IllegalStateException e = assertThrows(IllegalStateException.class, core::recording);
      assertTrue(e.getMessage().contains("recording is off"), e.getMessage());
      assertTrue(e.getMessage().contains("CoreConfig.builder().recording("), e.getMessage());
    }
  }

  @Test
  default void recordingOffCompilesNoTapIntoAChain() throws Exception {
    for (boolean on : new boolean[] {false, true}) {
      CoreConfig.Builder config = CoreConfig.builder();
      if (on) {
        config.recording(RecordingOptions.ring(10));
      }
      try (PrimeCore core = newCore(config.build())) {
        List<String> stack = RunningStack.classesOfAChainIn(core);
        boolean tapped = stack.stream().anyMatch(c -> c.startsWith("dev.prime.Recording"));
        assertEquals(on, tapped, "recording " + (on ? "on" : "off") + ", stack " + stack);
      }
    }
  }

  @Test
  default void aClosedCoreLeavesNoSubscriberOnTheProgramsEventBlock() throws Exception {
    EventBlock<String> events = new EventBlock<>();
    Recording recording;
    try (PrimeCore core = recordingCore(10)) {
      Reader<String> words = core.source("words", events).reader();
      core.start();
      events.publish("before");
      assertEquals("before", takeOrFail(words));
      recording = core.recording();
      assertEquals(List.of("before"), recording.getAll("words"));
    }
    // A subscriber left by the core would hold the value published after close (its stamp).
    ReferenceQueue<String> collected = new ReferenceQueue<>();
    WeakReference<String> after = publishAndForget(events, collected);
    assertEquals(List.of("before"), recording.getAll("words"), "nothing recorded after close");
    assertEquals(1, recording.recorded("words"));
    for (int attempt = 0; attempt < 20 && collected.poll() == null; attempt++) {
      System.gc();
      if (collected.remove(100) != null) {
        break;
      }
    }
    assertNull(after.get(), "a subscriber of the closed core still holds the value published");
  }

  /** Publishes a fresh value to {@code events} and keeps only a weak reference to it. */
  private static WeakReference<String> publishAndForget(
      EventBlock<String> events, ReferenceQueue<String> collected) {
    String value = new String("after close".toCharArray());
    events.publish(value);
    return new WeakReference<>(value, collected);
  }

  @Test
  default void onlyEventSourcesAndChainsOfABlockAreRecorded() throws Exception {
    try (PrimeCore core = recordingCore(100)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      Reader<Integer> evens = numbers.filter(x -> x % 2 == 0).reader();
      Reader<Integer> pairs = numbers.flatMap(x -> List.of(x, x)).reader();
      CountDownLatch heard = new CountDownLatch(4);
      numbers.listen(x -> heard.countDown());
      Block<Integer, String> parity =
          core.ifThenElse(
                  x -> x % 2 == 0,
                  core.chain("even", (Integer x) -> "even"),
                  core.chain("odd", (Integer x) -> "odd"))
              .toBlock();
      core.start();
      for (int i = 1; i <= 4; i++) {
        events.publish(i);
      }
      assertEquals(List.of(2, 4), takeOrFail(evens, 2));
      assertEquals(List.of(1, 1, 2, 2, 3, 3, 4, 4), takeOrFail(pairs, 8));
      assertTrue(heard.await(10, TimeUnit.SECONDS), "the listener heard every value");
      assertEquals("odd", parity.process(1));
      assertEquals("even", parity.process(2));

      Recording recording = core.recording();
      assertEquals(List.of("numbers", "even", "odd"), List.copyOf(recording.names()));
      assertEquals(List.of(1, 2, 3, 4), recording.getAll("numbers"));
      assertEquals(List.of("even"), recording.getAll("even"));
      assertEquals(List.of("odd"), recording.getAll("odd"));
      for (String notRecorded :
          List.of("filter(numbers)", "flatMap(numbers)", "listen(numbers)", "if(even|odd)")) {
        IllegalArgumentException e =
            assertThrows(IllegalArgumentException.class, () -> recording.getAll(notRecorded));
        assertTrue(e.getMessage().contains("numbers"), e.getMessage());
      }
    }
  }

  @Test
  default void getWaitsForAFirstValueUpToItsTimeout() throws Exception {
    try (PrimeCore core = recordingCore(10)) {
      EventBlock<String> events = new EventBlock<>();
      core.source("words", events);
      core.start();
      Recording recording = core.recording();
      assertEquals(Optional.empty(), recording.tryGet("words"));
      long start = System.nanoTime();
      NoSuchElementException none =
          assertThrows(
              NoSuchElementException.class,
              () -> recording.get("words", Duration.ofMillis(200)));
      assertTrue(System.nanoTime() - start >= TimeUnit.MILLISECONDS.toNanos(200));
      assertTrue(none.getMessage().contains("'words'"), none.getMessage());

      CountDownLatch waiting = new CountDownLatch(1);
      CompletableFuture<String> got =
          CompletableFuture.supplyAsync(
              () -> {
                waiting.countDown();
                try {
                  return recording.get("words", patience());
                } catch (InterruptedException e) {
                  throw new IllegalStateException(e);
                }
              });
      assertTrue(waiting.await(patience().toSeconds(), TimeUnit.SECONDS));
      events.publish("hello");
      assertEquals("hello", got.get(patience().toSeconds(), TimeUnit.SECONDS));
    }
  }

  @Test
  default void getDoesNotWaitOnAClosedCoreAndItsRecordingStaysReadable() throws Exception {
    PrimeCore core = recordingCore(10);
    Recording recording;
    try {
      EventBlock<String> events = new EventBlock<>();
      core.source("words", events);
      core.chain("never", (Integer x) -> x);
      core.start();
      events.publish("hello");
      recording = core.recording();
    } finally {
      core.close();
    }
    long closedAt = System.nanoTime();
    NoSuchElementException closed =
        assertThrows(NoSuchElementException.class, () -> recording.get("never", patience()));
    assertTrue(System.nanoTime() - closedAt < TimeUnit.SECONDS.toNanos(5), "get waited");
    assertTrue(closed.getMessage().contains("closed"), closed.getMessage());
    assertEquals("hello", recording.get("words"), "a closed core's recording can be read");
  }

  @Test
  default void sequenceNumbersAreGapFreeAndInOrderUnderConcurrentPublishers() throws Exception {
    int threads = 4;
    int each = 100;
    try (PrimeCore core = recordingCore(threads * each)) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source("concurrent", events);
      core.start();
      CountDownLatch go = new CountDownLatch(1);
      List<CompletableFuture<Void>> publishers = new ArrayList<>();
      for (int t = 0; t < threads; t++) {
        int base = t * each;
        publishers.add(
            CompletableFuture.runAsync(
                () -> {
                  try {
                    assertTrue(go.await(patience().toSeconds(), TimeUnit.SECONDS));
                  } catch (InterruptedException e) {
                    throw new IllegalStateException(e);
                  }
                  for (int i = 0; i < each; i++) {
                    events.publish(base + i);
                  }
                }));
      }
      go.countDown();
      CompletableFuture.allOf(publishers.toArray(CompletableFuture[]::new))
          .get(patience().toSeconds(), TimeUnit.SECONDS);

      List<RecordedValue<Integer>> all = core.recording().getAllStamped("concurrent");
      assertEquals(
          LongStream.range(0, threads * each).boxed().toList(),
          all.stream().map(RecordedValue::sequence).toList());
      for (int t = 0; t < threads; t++) { // each publisher's values in its order, stamps growing
        int base = t * each;
        List<RecordedValue<Integer>> own =
            all.stream().filter(e -> e.value() >= base && e.value() < base + each).toList();
        assertEquals(each, own.size());
        for (int i = 0; i < each; i++) {
          assertEquals(base + i, own.get(i).value());
          if (i > 0) {
            assertTrue(own.get(i).monotonicNanos() >= own.get(i - 1).monotonicNanos(), "at " + i);
            assertFalse(own.get(i).wallTime().isBefore(own.get(i - 1).wallTime()), "at " + i);
          }
        }
      }
    }
  }

  @Test
  default void aFullRingKeepsTheLatestAndCountsWhatItDropped() throws Exception {
    try (PrimeCore core = recordingCore(5)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out =
          core.source("numbers", events).then(core.chain("same", (Integer x) -> x)).reader();
      core.start();
      for (int i = 1; i <= 12; i++) {
        events.publish(i);
      }
      assertEquals(12, takeOrFail(out, 12).get(11));
      Recording recording = core.recording();
      for (String name : List.of("numbers", "same")) {
        assertEquals(List.of(8, 9, 10, 11, 12), recording.getAll(name), name);
        assertEquals(7, recording.dropped(name), name);
        assertEquals(12, recording.recorded(name), name);
        assertEquals(
            List.of(7L, 8L, 9L, 10L, 11L),
            recording.getAllStamped(name).stream().map(RecordedValue::sequence).toList());
        assertEquals(List.of(), recording.getRange(name, 0, 7), name);
        assertEquals(List.of(8, 9), recording.getRange(name, 5, 9), name);
        assertEquals(12, (int) recording.get(name));
      }
    }
  }

  @Test
  default void aPublishTheMediaRefusesIsNotRecorded() throws Exception {
    int capacity = 2;
    CountDownLatch firstInside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder()
            .publishTimeout(Duration.ofMillis(200))
            .recording(RecordingOptions.ring(100))
            .build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out =
          core.source("numbers", events)
              .then(stuckChain(core, "stuck", firstInside, release))
              .reader();
      core.start();
      fillStuckInput(events, firstInside, capacity);
      assertThrows(dev.prime.QueueFullException.class, () -> events.publish(999));
      release.countDown();
      int last = -1;
      // the stuck service's input has room again once 2 came out (on a busy machine that can take
      // longer than the publish timeout, so the next publish waits for it rather than racing it)
      for (int i = 0; i < 5 && last != 2; i++) { // a plain reader may miss the oldest outputs
        last = takeOrFail(out);
      }
      assertEquals(2, last, "the values the input held came out once released");
      events.publish(3);
      last = takeOrFail(out);
      assertEquals(3, last, "the last output arrived");
      Recording recording = core.recording();
      assertEquals(List.of(0, 1, 2, 3), recording.getAll("numbers"), "the refused 999 is not");
      assertEquals(
          List.of(0L, 1L, 2L, 3L),
          recording.getAllStamped("numbers").stream().map(RecordedValue::sequence).toList());
      assertEquals(List.of(0, 1, 2, 3), recording.getAll("stuck"));
    }
  }

  @Test
  default void recordingsOfTwoCoresMergeByWallClockTime() throws Exception {
    try (PrimeCore first = recordingCore(10);
        PrimeCore second = recordingCore(10)) {
      EventBlock<String> a = new EventBlock<>();
      EventBlock<String> b = new EventBlock<>();
      first.source("pose", a);
      second.source("pose", "Pose", b);
      Chain<String, String> upper = second.chain("upper", (String s) -> s.toUpperCase());
      Block<String, String> upperBlock = upper.toBlock();
      first.start();
      second.start();
      List<EventBlock<String>> order = List.of(a, b, a, b);
      for (int i = 0; i < order.size(); i++) {
        awaitNextMicrosecond(Instant.now());
        order.get(i).publish("p" + i);
      }
      assertEquals("X", upperBlock.process("x"));

      Recording merged = Recording.merge(first.recording(), second.recording());
      assertEquals(List.of("pose", "upper"), List.copyOf(merged.names()));
      assertEquals(List.of("p0", "p1", "p2", "p3"), merged.getAll("pose"));
      assertEquals(
          List.of(0L, 0L, 1L, 1L),
          merged.getAllStamped("pose").stream().map(RecordedValue::sequence).toList(),
          "each entry keeps the sequence number of the core that recorded it");
      assertEquals(Optional.of("Pose"), merged.pseudoname("pose"));
      assertEquals("X", merged.get("upper"));
      assertEquals(4, merged.recorded("pose"));
      b.publish("later");
      assertEquals("p3", merged.get("pose"), "a merged recording is a copy");
    }
  }

  /** Waits (busily, at most 1 s) until the wall clock has moved past {@code then}. */
  @Test
  default void aSubscriberSeesEveryValueAsRecordedPastTheRingAndThrowingIsCounted()
      throws Exception {
    try (PrimeCore core = recordingCore(2)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader =
          core.source("numbers", events).then(core.chain("double", (Integer x) -> x * 2)).reader();
      core.start();
      Recording recording = core.recording();
      java.util.Map<String, List<RecordedValue<Object>>> seen =
          new java.util.concurrent.ConcurrentHashMap<>();
      CountDownLatch all = new CountDownLatch(20);
      Recording.Subscription listening =
          recording.subscribe(
              v -> {
                seen.computeIfAbsent(v.service(), n -> new java.util.concurrent.CopyOnWriteArrayList<>())
                    .add(v);
                all.countDown();
              });
      Recording.Subscription throwing =
          recording.subscribe(
              v -> {
                throw new IllegalStateException("a listener bug");
              });
      for (int i = 1; i <= 10; i++) {
        events.publish(i);
      }
      assertEquals(10, takeOrFail(reader, 10).size());
      assertTrue(all.await(20, TimeUnit.SECONDS), "the subscriber saw " + seen);
      assertEquals(8, recording.dropped("numbers")); // the ring kept 2, the subscriber all 10
      assertEquals(LongStream.range(0, 10).boxed().toList(),
          seen.get("numbers").stream().map(RecordedValue::sequence).toList());
      assertEquals(List.of(1, 2, 3, 4, 5, 6, 7, 8, 9, 10),
          seen.get("numbers").stream().map(RecordedValue::value).toList());
      assertEquals(List.of(2, 4, 6, 8, 10, 12, 14, 16, 18, 20),
          seen.get("double").stream().map(RecordedValue::value).toList());
      assertEquals(20, throwing.failures());
      assertEquals(0, listening.failures());

      listening.close();
      throwing.close();
      events.publish(11);
      assertEquals(22, takeOrFail(reader));
      assertEquals(11, recording.recorded("numbers"));
      assertEquals(10, seen.get("numbers").size(), "a closed subscription is not called");
      assertEquals(20, throwing.failures());
    }
  }

  /**
   * {@link dev.prime.RecordingListener}: "An exception it throws is caught, counted in {@link
   * Recording.Subscription#failures()}, and does not reach the controller": also an {@link
   * AssertionError} and a checked exception (a Kotlin writer to disk throws {@code IOException}
   * without declaring it), not only a {@code RuntimeException}.
   */
  @Test
  default void aSubscriberThrowingAnErrorOrACheckedExceptionIsCountedAndNeverReachesTheCaller()
      throws Exception {
    try (PrimeCore core = recordingCore(10)) {
      Block<Integer, Integer> doubled = core.chain("double", (Integer x) -> x * 2).toBlock();
      core.start();
      Recording recording = core.recording();
      java.util.concurrent.atomic.AtomicInteger calls = new java.util.concurrent.atomic.AtomicInteger();
      Recording.Subscription throwing =
          recording.subscribe(
              v -> {
                if (calls.incrementAndGet() % 2 == 1) {
                  throw new AssertionError("a listener's assertion");
                }
                throw RecordingConformance.<RuntimeException>sneaky(
                    new java.io.IOException("the disk is full"));
              });
      List<Integer> out = new ArrayList<>();
      for (int i = 1; i <= 4; i++) {
        out.add(doubled.process(i));
      }
      assertEquals(List.of(2, 4, 6, 8), out, "no listener failure reached the caller");
      assertEquals(4, recording.recorded("double"));
      assertEquals(4, throwing.failures(), "every failure of the listener is counted");
    }
  }

  /** Throws any throwable, checked or not, without declaring it. */
  @SuppressWarnings("unchecked")
  private static <E extends Throwable> RuntimeException sneaky(Throwable t) throws E {
    throw (E) t;
  }

  private static void awaitNextMicrosecond(Instant then) {
    long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(1);
    for (int i = 0; i < 10_000_000 && System.nanoTime() < deadline; i++) {
      if (Instant.now().isAfter(then)) {
        return;
      }
    }
    throw new AssertionError("the wall clock did not move for 1 s");
  }
}
