package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.ErrorHandler;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.optimus.DeadLetter;
import dev.prime.optimus.KryoCodec;
import dev.prime.optimus.OptimusCore;
import java.nio.ByteBuffer;
import java.nio.charset.StandardCharsets;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.Random;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;
import redis.clients.jedis.Jedis;

/**
 * Bad things inside a service's input and inside a block: hostile bytes are dead-lettered with a
 * reason and the service goes on (classic); a crafted request whose reply key points outside the
 * namespace, at a key of the wrong type, or at another list of the topology is dead-lettered and
 * writes nothing (issue 9 item 5); a block throwing {@link AssertionError} does not stop its
 * service, and the error handler gets it (item 4).
 */
class HostileInputTest {
  private static final Duration PATIENCE = Duration.ofSeconds(15);

  @Test
  void hostileBytesAreDeadLetteredWithReasonsAndTheServiceGoesOn() throws Exception {
    String name = "hostile";
    KryoCodec codec = KryoCodec.standard();
    Map<String, byte[]> named = new LinkedHashMap<>();
    named.put("empty entry", new byte[0]);
    named.put("one byte", new byte[] {EnvelopeBytes.MAGIC});
    named.put("plain text", "not an envelope".getBytes(StandardCharsets.UTF_8));
    named.put("wrong magic", ByteBuffer.allocate(20).put((byte) 0x51).array());
    named.put("unknown kind", EnvelopeBytes.raw((byte) 9, 9001, new byte[] {1, 2}));
    named.put("truncated id", new byte[] {EnvelopeBytes.MAGIC, EnvelopeBytes.VALUE, 1, 2, 3});
    named.put("reply key longer than the entry", EnvelopeBytes.raw(EnvelopeBytes.REQUEST, 9002, new byte[] {(byte) 0xFF, (byte) 0xFF, 1}));
    named.put("garbage payload", EnvelopeBytes.value(9003, new byte[] {-1, -2, -3, -4, -5}));
    byte[] text = codec.encode("a string long enough to be cut in the middle");
    named.put("truncated payload", EnvelopeBytes.value(9004, Arrays.copyOf(text, text.length / 2)));
    named.put("reply in a service input", EnvelopeBytes.raw(EnvelopeBytes.REPLY_OK, 9005, new byte[] {0}));
    named.put("error reply with a bad length", EnvelopeBytes.raw(EnvelopeBytes.REPLY_ERROR, 9006, new byte[] {0, 1, 'x', 0x7F, 0, 0, 0}));
    named.put("value of the wrong type", EnvelopeBytes.value(9007, codec.encode("not a Long")));
    named.put("absent value", EnvelopeBytes.value(9008, null));
    List<byte[]> random = new ArrayList<>();
    Random bytes = new Random(20261123);
    for (int i = 0; i < FaultMode.current().randomHostile; i++) {
      byte[] entry;
      if (i % 2 == 0) {
        entry = new byte[bytes.nextInt(64)];
        bytes.nextBytes(entry);
        if (entry.length > 0 && entry[0] == EnvelopeBytes.MAGIC) entry[0] = 0;
      } else {
        byte[] payload = new byte[1 + bytes.nextInt(48)];
        bytes.nextBytes(payload);
        entry = EnvelopeBytes.value(1_000_000 + i, payload);
      }
      random.add(entry);
    }
    int hostile = named.size() + random.size();
    int good = 500;

    CopyOnWriteArrayList<Throwable> handled = new CopyOnWriteArrayList<>();
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        OptimusCore core = Cores.builder(redis.url(), name, StreamTopology.WIDE_RETENTION, (s, i, e) -> handled.add(e))
            .hosts("stamp").build();
        Jedis raw = redis.client()) {
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      core.start();
      LedgerFeed.start(stream.observer(), sink, name);
      Ledger ledger = new Ledger(0, good);
      sink.set(ledger);
      byte[] input = TopologyKeys.bytes(new TopologyKeys(name).serviceInput("stamp"));
      for (long id = 0; id < good / 2; id++) ids.publish(id);
      for (byte[] entry : named.values()) raw.rpush(input, entry);
      for (byte[] entry : random) raw.rpush(input, entry);
      for (long id = good / 2; id < good; id++) ids.publish(id);
      assertTrue(ledger.awaitAll(PATIENCE), "the service went on after the hostile entries: " + ledger.counts());
      Bounded.await(PATIENCE, () -> core.deadLetters("stamp").size() + ledger.unexpected() >= hostile);

      List<DeadLetter> letters = core.deadLetters("stamp");
      long withReason = letters.stream().filter(l -> !l.getReason().isBlank()).count();
      long reasons = letters.stream().map(l -> l.getReason().replaceAll("[0-9]+", "N")).distinct().count();
      Figures.report("hostile bytes: " + hostile + " entries (" + named.size() + " kinds + " + random.size() + " random), "
          + letters.size() + " dead-lettered (" + withReason + " with a reason, " + reasons + " distinct reasons), "
          + ledger.unexpected() + " decoded as values, " + handled.size() + " reported to the error handler; good values: "
          + ledger.counts());
      assertEquals(0, ledger.lost(), ledger.counts());
      assertEquals(0, ledger.reordered(), ledger.counts());
      List<String> missing = new ArrayList<>();
      for (Map.Entry<String, byte[]> kind : named.entrySet()) {
        if (letters.stream().noneMatch(letter -> Arrays.equals(letter.bytes(), kind.getValue()))) missing.add(kind.getKey());
      }
      assertEquals(List.of(), missing, "named hostile kinds not found among the dead letters as they were pushed: " + letters);
      assertEquals(0, ledger.unexpected(), "no hostile entry came out as a value: " + ledger.counts());
      assertEquals(hostile, letters.size(), "every hostile entry is dead-lettered: " + letters);
      assertEquals(letters.size(), withReason, "every dead letter says why");
    }
  }

  @Test
  void craftedReplyKeysAreDeadLetteredAndWriteNothing() throws Exception {
    String name = "crafted";
    KryoCodec codec = KryoCodec.standard();
    TopologyKeys keys = new TopologyKeys(name);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        OptimusCore core = Cores.core(redis.url(), name, 1024, "echo", "other");
        Jedis raw = redis.client()) {
      Block<Long, Long> echo = core.<Long, Long>chain("echo", x -> x).toBlock();
      core.<Long, Long>chain("other", x -> x).toBlock();
      core.start();
      assertEquals(1L, echo.process(1L), "a call before the attack");
      raw.rpush("victim:list", "a", "b", "c");
      String codecBefore = raw.get(keys.codec());
      byte[] input = TopologyKeys.bytes(keys.serviceInput("echo"));
      raw.rpush(input, EnvelopeBytes.request(7001, TopologyKeys.bytes("victim:list"), codec.encode(7L)));
      raw.rpush(input, EnvelopeBytes.request(7002, TopologyKeys.bytes(keys.codec()), codec.encode(8L)));
      raw.rpush(input, EnvelopeBytes.request(7003, TopologyKeys.bytes(keys.serviceInput("other")), codec.encode(9L)));

      long started = System.nanoTime();
      Optional<Long> after = call(echo, 10L);
      long tookNanos = System.nanoTime() - started;
      Bounded.await(PATIENCE, () -> core.deadLetters("echo").size() >= 3);
      List<DeadLetter> letters = core.deadLetters("echo");
      List<String> victim = raw.lrange("victim:list", 0, -1);
      String codecAfter = raw.get(keys.codec());
      long otherLength = raw.llen(keys.serviceInput("other"));
      List<DeadLetter> otherLetters = core.deadLetters("other");
      Figures.report("crafted reply keys: 3 requests, " + letters.size() + " dead-lettered, victim:list "
          + (victim.equals(List.of("a", "b", "c")) ? "untouched" : "changed to " + victim.size() + " entries")
          + ", codec key " + (codecBefore.equals(codecAfter) ? "untouched" : "changed") + ", other service's input "
          + (otherLength == 0 && otherLetters.isEmpty() ? "untouched" : "written to") + ", next call "
          + (after.isPresent() ? "answered in " + Figures.seconds(tookNanos) : "failed"));
      assertEquals(List.of("a", "b", "c"), victim, "nothing is written outside the namespace");
      assertEquals(codecBefore, codecAfter);
      assertEquals(0, otherLength + otherLetters.size(), "nothing is written to another service's list");
      assertEquals(Optional.of(10L), after, "the service goes on after the crafted entries");
      assertEquals(3, letters.size(), "each crafted request is dead-lettered: " + letters);
      for (DeadLetter letter : letters) assertFalse(letter.getReason().isBlank(), letter.toString());
    }
  }

  @Test
  void anAssertionErrorInABlockDoesNotStopItsService() throws Exception {
    List<String> reported = new CopyOnWriteArrayList<>();
    ErrorHandler handler = (service, input, error) -> reported.add(service + "/" + input + "/" + error.getClass().getSimpleName());
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        OptimusCore core = Cores.builder(redis.url(), "assertion", 1024, handler).callTimeout(Duration.ofSeconds(5)).build()) {
      EventBlock<Long> numbers = new EventBlock<>();
      Reader<Long> out = core.source("numbers", numbers).then(core.<Long, Long>chain("picky", x -> {
        if (x % 10 == 3) throw new AssertionError("picky about " + x);
        return x;
      })).reader();
      Block<Long, Long> strict = core.<Long, Long>chain("strict", x -> {
        if (x == 1) throw new AssertionError("strict about " + x);
        return x;
      }).toBlock();
      core.start();
      for (long x = 0; x < 20; x++) numbers.publish(x);
      List<Long> received = new ArrayList<>();
      for (int i = 0; i < 18; i++) {
        Optional<Long> next = out.take(PATIENCE);
        if (next.isEmpty()) break;
        received.add(next.get());
      }
      String firstCall = describe(() -> strict.process(1L));
      String secondCall = describe(() -> strict.process(2L));
      Figures.report("AssertionError in a block: 20 values, 2 throwing, " + received.size() + " of 18 came out, "
          + reported.size() + " reported to the error handler; calls: " + firstCall + ", then " + secondCall);
      List<Long> expected = new ArrayList<>();
      for (long x = 0; x < 20; x++) if (x % 10 != 3) expected.add(x);
      assertEquals(expected, received, "the service goes on after an AssertionError");
      assertEquals(List.of("picky/3/AssertionError", "picky/13/AssertionError"), reported,
          "the handler gets the service, the input and the block's own throwable");
      assertTrue(firstCall.startsWith("threw"), firstCall);
      assertEquals("returned 2", secondCall, "the called service goes on after an AssertionError");
    }
  }

  private static Optional<Long> call(Block<Long, Long> block, long value) {
    try {
      return Optional.ofNullable(block.process(value));
    } catch (RuntimeException e) {
      return Optional.empty();
    }
  }

  private static String describe(java.util.function.Supplier<Long> call) {
    try {
      return "returned " + call.get();
    } catch (RuntimeException | AssertionError e) {
      return "threw " + e.getClass().getSimpleName();
    }
  }
}
