package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotSame;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.Tick;
import dev.prime.Tuple2;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;

/**
 * Values have one semantics: with {@link CoreConfig.Builder#copyValues} (always, on a media that
 * carries values between processes) every value that crosses a service boundary is a copy, so a
 * mutation after the hand-over is never seen by the receiver, and a type the codec refuses fails
 * the publish or the call. The C#-era "clone" behaviour.
 */
public interface ValueCopyConformance extends ConformanceBase {

  /** A mutable type no codec is told about. */
  final class Unshippable {
    int count;
  }

  private PrimeCore copyingCore() {
    return newCore(CoreConfig.builder().copyValues(copyCodec()).build());
  }

  @Test
  default void aValueMutatedAfterPublishIsNotSeenChangedByAReader() throws InterruptedException {
    try (PrimeCore core = copyingCore()) {
      EventBlock<List<Integer>> events = new EventBlock<>();
      Source<List<Integer>> source = core.source(events);
      Reader<List<Integer>> first = source.reader();
      Reader<List<Integer>> second = source.reader();
      core.start();
      List<Integer> value = new ArrayList<>(List.of(1, 2));
      events.publish(value);
      value.add(3);
      List<Integer> read = takeOrFail(first);
      assertEquals(List.of(1, 2), read, "the reader saw the publisher's later mutation");
      read.add(4);
      assertEquals(List.of(1, 2), takeOrFail(second), "a reader saw another reader's mutation");
    }
  }

  /**
   * A published value is copied whole, an object inside it included, and each read gets a copy of
   * its own, whichever call reads it: a publisher that changes the values it published, and a
   * list inside each, changes nothing that a reader made after the publishes reads from the
   * retained values with {@link Reader#poll()}, {@link Reader#take()} and {@link Reader#drain()};
   * and what that reader then changes, inside too, is not seen by another late reader.
   */
  @Test
  default void aLateReaderGetsTheRetainedValuesAsPublishedWithEveryKindOfRead()
      throws InterruptedException {
    try (PrimeCore core = copyingCore()) {
      EventBlock<List<List<Integer>>> events = new EventBlock<>();
      Source<List<List<Integer>>> source = core.source(events);
      core.start();
      List<List<List<Integer>>> published = new ArrayList<>();
      List<List<List<Integer>>> expected = new ArrayList<>();
      for (int i = 0; i < 4; i++) {
        List<List<Integer>> value = new ArrayList<>();
        value.add(new ArrayList<>(List.of(i)));
        events.publish(value);
        published.add(value);
        expected.add(List.of(List.of(i)));
      }
      for (List<List<Integer>> value : published) {
        value.get(0).add(99);
        value.add(new ArrayList<>(List.of(-1)));
      }
      Reader<List<List<Integer>>> late = source.reader();
      List<List<List<Integer>>> read = new ArrayList<>();
      late.poll().ifPresent(read::add);
      read.add(takeOrFail(late));
      read.addAll(late.drain());
      assertEquals(expected, read, "poll, take, drain: the publisher's later changes were seen");
      for (List<List<Integer>> value : read) {
        value.get(0).add(77);
      }
      assertEquals(expected, source.reader().drain(), "another reader saw the first one's changes");
    }
  }

  @Test
  default void aServiceGetsAndGivesCopies() throws InterruptedException {
    try (PrimeCore core = copyingCore()) {
      EventBlock<List<Integer>> events = new EventBlock<>();
      Source<List<Integer>> source = core.source(events);
      Reader<List<Integer>> direct = source.reader();
      Reader<List<Integer>> grown =
          core.link(
                  source,
                  core.chain(
                      (List<Integer> list) -> {
                        list.add(99); // a block that mutates its input
                        return list;
                      }))
              .reader();
      core.start();
      events.publish(new ArrayList<>(List.of(1)));
      assertEquals(List.of(1, 99), takeOrFail(grown));
      assertEquals(List.of(1), takeOrFail(direct), "the service's mutation reached another reader");
    }
  }

  /**
   * {@link dev.prime.ValueCodec}, "Nulls": "Neither method sees {@code null}". With a codec
   * that copies values across every service boundary ({@link #newCoreWithCodec}), a chain whose
   * block returns {@code null} gives its synchronous caller {@code null}, a linked chain passes a
   * {@code null} to its next chain (a service of its own on a media that does not fuse them), and
   * a chain linked to a source publishes nothing for one: the codec
   * is never given a {@code null} to encode.
   */
  @Test
  default void theCodecNeverSeesANull() throws InterruptedException {
    List<String> sawNull = Collections.synchronizedList(new ArrayList<>());
    dev.prime.ValueCodec inner = copyCodec();
    dev.prime.ValueCodec watching =
        new dev.prime.ValueCodec() {
          @Override
          public byte[] encode(Object value) {
            if (value == null) {
              sawNull.add("encode(null)");
              throw new IllegalArgumentException("the kit's codec was given null to encode");
            }
            return inner.encode(value);
          }

          @Override
          public Object decode(byte[] bytes) {
            if (bytes == null) {
              sawNull.add("decode(null)");
              throw new IllegalArgumentException("the kit's codec was given null to decode");
            }
            return inner.decode(bytes);
          }

          @Override
          public String toString() {
            return "null-watching " + inner;
          }
        };
    try (PrimeCore core = newCoreWithCodec(CoreConfig.builder().copyValues(watching).build())) {
      Block<Integer, Integer> nothing = core.chain("nothing", (Integer x) -> (Integer) null).toBlock();
      Block<Integer, String> linked =
          core.chain("maybe", (Integer x) -> x > 0 ? x : null)
              .then(core.chain("show", (Integer x) -> x == null ? "none" : "v" + x))
              .toBlock();
      EventBlock<Integer> events = new EventBlock<>();
      Reader<String> served =
          core.source("numbers", events)
              .then(
                  core.chain("served-maybe", (Integer x) -> x > 0 ? x : null)
                      .then(core.chain("served-show", (Integer x) -> x == null ? null : "s" + x)))
              .reader();
      core.start();
      assertEquals(null, nothing.process(1));
      assertEquals("none", linked.process(-1));
      assertEquals("v2", linked.process(2));
      events.publish(-1);
      events.publish(4);
      assertEquals("s4", takeOrFail(served));
      assertEquals(List.of(), sawNull, "the codec was given a null");
    }
  }

  @Test
  default void aSyncCallCopiesItsInputAndResult() {
    try (PrimeCore core = copyingCore()) {
      List<Integer> kept = new ArrayList<>();
      Chain<List<Integer>, List<Integer>> chain =
          core.chain(
              "grow",
              (List<Integer> list) -> {
                list.add(99);
                kept.clear();
                kept.addAll(list);
                return kept;
              });
      core.start();
      Block<List<Integer>, List<Integer>> block = chain.toBlock();
      List<Integer> input = new ArrayList<>(List.of(1));
      List<Integer> result = block.process(input);
      assertEquals(List.of(1), input, "the block's mutation reached the caller's input");
      assertEquals(List.of(1, 99), result);
      result.add(100);
      assertEquals(List.of(1, 99), block.process(new ArrayList<>(List.of(1))));
    }
  }

  /**
   * The in-memory media pass values by reference unless told to copy: a synchronous call's
   * block gets the caller's very input and the caller its very result, and a published value
   * reaches every reader and every service as the very object published. With {@code
   * copyValues}, chains linked together are one service, so the value one returns is the very
   * object the next gets; only what crosses into and out of the linked chain is copied.
   */
  @Test
  default void theInMemoryMediaPassValuesByReferenceAndLinkedChainsNeverCopy() throws Exception {
    Assumptions.assumeTrue(
        blocksRunOnTheCallersThread(), "in-memory media: values stay in this process");
    try (PrimeCore core = newCore()) {
      EventBlock<List<Integer>> events = new EventBlock<>();
      Source<List<Integer>> source = core.source(events);
      Reader<List<Integer>> reader = source.reader();
      List<Object> served = Collections.synchronizedList(new ArrayList<>());
      Reader<Boolean> service =
          core.link(
                  source,
                  core.chain(
                      (List<Integer> list) -> {
                        served.add(list);
                        return true;
                      }))
              .reader();
      List<Integer> result = new ArrayList<>();
      List<Object> received = new ArrayList<>();
      Block<List<Integer>, List<Integer>> block =
          core.chain(
                  "same",
                  (List<Integer> list) -> {
                    received.add(list);
                    return result;
                  })
              .toBlock();
      core.start();
      List<Integer> input = new ArrayList<>(List.of(1));
      assertSame(result, block.process(input), "the caller gets the block's very result");
      assertSame(input, received.get(0), "the block gets the caller's very input");
      List<Integer> published = new ArrayList<>(List.of(2));
      events.publish(published);
      assertSame(published, takeOrFail(reader), "a reader gets the very value published");
      assertEquals(true, takeOrFail(service));
      assertSame(published, served.get(0), "a service gets the very value published");
    }
    try (PrimeCore core = copyingCore()) {
      List<Object> handedOver = new ArrayList<>();
      Block<List<Integer>, List<Integer>> linked =
          core.chain(
                  "first",
                  (List<Integer> list) -> {
                    List<Integer> out = new ArrayList<>(list);
                    handedOver.add(out);
                    return out;
                  })
              .then(
                  core.chain(
                      "second",
                      (List<Integer> list) -> {
                        handedOver.add(list);
                        return list;
                      }))
              .toBlock();
      core.start();
      List<Integer> output = linked.process(new ArrayList<>(List.of(3)));
      assertEquals(List.of(3), output);
      assertSame(handedOver.get(0), handedOver.get(1), "between linked chains nothing is copied");
      assertNotSame(handedOver.get(1), output, "what leaves the linked chain is a copy");
    }
  }

  @Test
  default void aValueTheCodecRefusesFailsThePublishAndTheCall() {
    try (PrimeCore core = copyingCore()) {
      EventBlock<Unshippable> events = new EventBlock<>();
      core.source(events);
      Chain<Unshippable, Integer> chain = core.chain(u -> u.count);
      core.start();
      assertThrows(IllegalArgumentException.class, () -> events.publish(new Unshippable()));
      Block<Unshippable, Integer> block = chain.toBlock();
      assertThrows(IllegalArgumentException.class, () -> block.process(new Unshippable()));
    }
  }

  /**
   * A template and its parts are one chain, in one service: on the in-memory media, with {@link
   * CoreConfig.Builder#copyValues}, the parts of a union get the very same input, and a branch
   * may return a value of a type the codec refuses, as long as the value stays in the service; with
   * metrics on too (a metered template runs the generic template blocks on every media).
   */
  @Test
  default void aTemplateCopiesNothingBetweenItsPartsOnTheInMemoryMedia() {
    Assumptions.assumeTrue(
        blocksRunOnTheCallersThread(), "the in-memory media: a template is one service there");
    for (boolean metrics : new boolean[] {false, true}) {
      CoreConfig config = CoreConfig.builder().copyValues(copyCodec()).metrics(metrics).build();
      try (PrimeCore core = newCore(config)) {
        List<Object> seen = Collections.synchronizedList(new ArrayList<>());
        Block<List<Integer>, Integer> union =
            core.union(
                    core.chain("left", (List<Integer> list) -> seen.add(list) ? list.size() : 0),
                    core.chain("right", (List<Integer> list) -> seen.add(list) ? list.size() : 0))
                .then(core.chain("sum", (Tuple2<Integer, Integer> t) -> t.first() + t.second()))
                .toBlock();
        Block<Integer, Integer> branch =
            core.ifThenElse(
                    (Integer x) -> x > 0,
                    core.chain("make", (Integer x) -> unshippable(x)),
                    core.chain("makeNone", (Integer x) -> unshippable(0)))
                .then(core.chain("count", (Unshippable u) -> u.count))
                .toBlock();
        core.start();
        assertEquals(2, union.process(new ArrayList<>(List.of(7))), "metrics " + metrics);
        assertSame(seen.get(0), seen.get(1), "the union's parts got the very same input, metrics " + metrics);
        assertEquals(5, branch.process(5), "a value that stays in the service is not copied, metrics " + metrics);
      }
    }
  }

  /**
   * The core's own value types cross service boundaries as copies too: the tuples of a zip (a
   * tuple inside a tuple as well) reach a reader and a chain linked after the zip, on a core whose
   * values all go through the kit's copy codec, and nothing reaches the error handler.
   */
  @Test
  default void aZipsTuplesAreCopiedThroughTheCodec() throws InterruptedException {
    List<String> failures = Collections.synchronizedList(new ArrayList<>());
    CoreConfig config = copyingCollectingFailures(failures);
    try (PrimeCore core = newCoreWithCodec(config)) {
      EventBlock<Integer> numbers = new EventBlock<>();
      EventBlock<String> names = new EventBlock<>();
      EventBlock<Boolean> flags = new EventBlock<>();
      Source<Tuple2<Tuple2<Integer, String>, Boolean>> zipped =
          core.zip(
              core.zip(core.source("numbers", numbers), core.source("names", names)),
              core.source("flags", flags));
      Reader<Tuple2<Tuple2<Integer, String>, Boolean>> reader = zipped.reader();
      Reader<String> described =
          zipped
              .then(
                  core.chain(
                      "describe",
                      (Tuple2<Tuple2<Integer, String>, Boolean> t) ->
                          t.first().first() + t.first().second() + t.second()))
              .reader();
      core.start();
      numbers.publish(1);
      names.publish("a");
      flags.publish(true);
      assertEquals(new Tuple2<>(new Tuple2<>(1, "a"), true), takeOrFail(reader));
      assertEquals("1atrue", takeOrFail(described));
      assertEquals(List.of(), failures, "failures");
    }
  }

  /**
   * A timer's ticks cross service boundaries as copies: they reach a reader and a chain linked
   * after the timer, on a core whose values all go through the kit's copy codec, and nothing
   * reaches the error handler.
   */
  @Test
  default void aTimersTicksAreCopiedThroughTheCodec() throws InterruptedException {
    List<String> failures = Collections.synchronizedList(new ArrayList<>());
    CoreConfig config = copyingCollectingFailures(failures);
    try (PrimeCore core = newCoreWithCodec(config)) {
      Source<Tick> ticks = core.timer("ticks", Duration.ofMillis(20));
      Reader<Tick> reader = ticks.reader();
      Reader<Long> counts = ticks.then(core.chain("count", Tick::count)).reader();
      core.start();
      Tick first = takeOrFail(reader);
      assertEquals(1L, first.count(), "the first tick's count");
      assertEquals(1L, takeOrFail(counts), "the count the chain after the timer read");
      assertEquals(List.of(), failures, "failures");
    }
  }

  private static Unshippable unshippable(int count) {
    Unshippable made = new Unshippable();
    made.count = count;
    return made;
  }

  /**
   * A config whose values all go through the kit's copy codec and whose error handler adds each
   * failure to {@code failures} as "service: error".
   */
  private CoreConfig copyingCollectingFailures(List<String> failures) {
    return CoreConfig.builder()
        .copyValues(copyCodec())
        .errorHandler((service, input, error) -> failures.add(service + ": " + error))
        .build();
  }
}
