package dev.prime.inspector;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.FaultProxy;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.function.Predicate;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.ValueSource;

/**
 * An Optimus service's queue depth while Redis cannot be read: the figures say it is unknown
 * ({@code "queueUnknown": true}, the page "queue ?"), not that the service has no queue, and show
 * the depth again once Redis answers. Redis is made unreachable by a proxy that closes every
 * connection at once; the event-stream test runs again with the proxy holding every reply back as
 * the kit's slow Redis does.
 */
class InspectorRedisUnreachableTest {
  private static final ObjectMapper JSON = new ObjectMapper();
  private static final Duration WAIT = Duration.ofSeconds(20);

  /** An Optimus core with metrics on, behind {@code proxy}, running source → "same". */
  private static OptimusCore meteredCore(FaultProxy proxy) {
    return OptimusCore.builder()
        .config(CoreConfig.builder().metrics(true).build())
        .redis(proxy.getUrl())
        .build();
  }

  /** The figures of "same" in the first posting (of at most 40, 20 s) that {@code test} accepts. */
  private static JsonNode sameFigures(
      InspectorHttpTest.RawStream stream, Predicate<JsonNode> test, String what) throws Exception {
    JsonNode same = null;
    for (int i = 0; i < 40; i++) {
      stream.until("event: figures", 50);
      same = JSON.readTree(stream.until("data: ", 5).substring(6)).path("nodes").path("same");
      if (test.test(same)) {
        return same;
      }
    }
    throw new AssertionError("no figures where " + what + "; the last: " + same);
  }

  @ParameterizedTest(name = "reply delay {0} ns")
  @ValueSource(longs = {0, FaultProxy.SLOW_REPLY_NANOS})
  void theFiguresSayAQueueIsUnknownWhileRedisCannotBeReadAndShowItAgainAfter(long replyDelayNanos)
      throws Exception {
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        FaultProxy proxy = new FaultProxy(redis.getUri(), replyDelayNanos);
        OptimusCore core = meteredCore(proxy)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out =
          core.source("numbers", events).then(core.chain("same", (Integer x) -> x)).reader();
      try (PrimeInspector inspector = PrimeInspector.start(core)) {
        core.start();
        events.publish(1);
        assertEquals(1, out.take(WAIT).orElseThrow());
        try (InspectorHttpTest.RawStream stream =
            new InspectorHttpTest.RawStream(inspector.uri(), "/api/events")) {
          assertEquals("HTTP/1.1 200 OK", stream.line());
          // the stream starts with the figures sampled last, perhaps before "same" took the value
          // (a depth of 1): a later posting, sampled after the take, reads 0
          JsonNode read =
              sameFigures(
                  stream,
                  n -> n.path("queueDepth").isNumber() && n.path("queueDepth").asLong() == 0,
                  "a depth of 0 once the value went through");
          assertFalse(read.has("queueUnknown"), "a depth that was read is known: " + read);

          proxy.refuse();
          JsonNode unknown =
              sameFigures(stream, n -> n.path("queueUnknown").asBoolean(), "the queue is unknown");
          assertTrue(unknown.get("queueDepth").isNull(), "no depth while unknown: " + unknown);

          proxy.restore();
          JsonNode again =
              sameFigures(stream, n -> n.path("queueDepth").isNumber(), "a depth once Redis is back");
          assertFalse(again.has("queueUnknown"), again.toString());
        }
      }
    }
  }

  @Test
  void thePageShowsAQueueQuestionMarkWhileRedisCannotBeRead() throws Exception {
    HeadlessChromium.requireBinary();
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        FaultProxy proxy = new FaultProxy(redis.getUri());
        OptimusCore core = meteredCore(proxy)) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source("numbers", events).then(core.chain("same", (Integer x) -> x));
      try (PrimeInspector inspector = PrimeInspector.start(core);
          HeadlessChromium chromium = HeadlessChromium.open(inspector.uri(), 1200, 800)) {
        core.start();
        String box = "document.querySelector('#diagram g.node[data-name=\"same\"]')";
        chromium.await(box + "?.getAttribute('data-queuedepth')", d -> d.asText().equals("0"), WAIT,
            "the box of 'same' should show its queue's depth, 0");
        proxy.refuse();
        chromium.await(box + "?.classList.contains('queue-unknown')", JsonNode::asBoolean, WAIT,
            "the box of 'same' should be marked: its queue depth is unknown");
        String figures = chromium.evaluate(box + ".querySelector('.figures').textContent").asText();
        assertTrue(figures.endsWith("queue ?"), "the figures of 'same' read: " + figures);
        String title = chromium.evaluate(box + ".querySelector('title').textContent").asText();
        assertTrue(title.contains("queue depth unknown"), "its title reads: " + title);
        assertFalse(
            chromium.evaluate(box + ".hasAttribute('data-queuedepth')").asBoolean(),
            "no depth attribute is left from before");
        proxy.restore();
        chromium.await(box + "?.classList.contains('queue-unknown')", v -> !v.asBoolean(), WAIT,
            "the mark should go once Redis answers again");
      }
    }
  }
}
