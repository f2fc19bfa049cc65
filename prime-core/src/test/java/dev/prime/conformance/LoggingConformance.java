package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.util.List;
import java.util.UUID;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.Test;

/**
 * Logging users can live with: one INFO line when a core starts, and a failing service's stack
 * trace once per burst, not once per value (the default error handler).
 */
public interface LoggingConformance extends ConformanceBase {

  /** {@return whether this media's tests log at INFO for dev.prime.PrimeCore} */
  default boolean logsStartLine() {
    return true;
  }

  @Test
  default void hundredFailuresInABurstLogOneStackTrace() throws InterruptedException {
    String service = "fails-" + UUID.randomUUID().toString().substring(0, 8);
    int failures = 100;
    CountDownLatch attempted = new CountDownLatch(failures);
    List<String> lines;
    try (CapturedStderr err = new CapturedStderr()) {
      try (PrimeCore core = newCore(CoreConfig.defaults())) {
        EventBlock<Integer> events = new EventBlock<>();
        core.link(
            core.source(events),
            core.chain(
                service,
                (Integer x) -> {
                  attempted.countDown();
                  throw new ErrorConformance.Boom("value " + x + " is bad");
                }));
        core.start();
        for (int i = 1; i <= failures; i++) {
          events.publish(i);
        }
        assertTrue(attempted.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      } // close waits for the service, so its last failure is handled (and logged) by now
      lines = err.lines();
    }
    List<String> mentions = lines.stream().filter(l -> l.contains("'" + service + "'")).toList();
    List<String> traces =
        lines.stream() // a stack trace opens with the exception alone on its line
            .filter(l -> l.startsWith("dev.prime.conformance.ErrorConformance$Boom: value"))
            .toList();
    assertEquals(1, traces.size(), "one stack trace for the burst; log:\n" + String.join("\n", lines));
    assertTrue(
        mentions.size() >= 1 && mentions.size() <= 4,
        "one ERROR line and at most a few summaries, not "
            + mentions.size()
            + ":\n"
            + String.join("\n", mentions));
    assertTrue(
        mentions.stream().anyMatch(l -> l.contains("more in the last")),
        "the rest of the burst is counted (at the latest when the core closes): " + mentions);
    assertTrue(
        lines.stream().filter(l -> l.contains("\tat ")).count() < 200,
        "one stack trace's frames, not a hundred");
  }

  @Test
  default void startIsLoggedOnceWithMediaAndServices() {
    if (!logsStartLine()) {
      return;
    }
    String service = "hosted-" + UUID.randomUUID().toString().substring(0, 8);
    List<String> starts;
    String coreName;
    try (CapturedStderr err = new CapturedStderr()) {
      try (PrimeCore core = newCore(CoreConfig.defaults())) {
        coreName = core.name();
        EventBlock<Integer> events = new EventBlock<>();
        core.link(core.source(events), core.chain(service, (Integer x) -> x));
        core.start();
      }
      starts =
          err.lines().stream()
              .filter(l -> l.contains("core '" + coreName + "' started on "))
              .toList();
    }
    assertEquals(1, starts.size(), String.valueOf(starts));
    String line = starts.get(0);
    assertTrue(line.contains(" INFO "), line);
    assertTrue(line.contains(service), "names the hosted services: " + line);
    assertTrue(line.matches(".*started on [a-z]+.*"), "names the media: " + line);
  }

  /**
   * Values a reader missed are logged at WARN like failures: the first of a burst in full, the
   * rest counted, at most one line per 10 s, and what is still counted when the core closes is
   * written then. So two bursts of misses within a test make two lines naming the source, the
   * second at the close, whose counts add up to every value missed, and {@code Reader.missed()}
   * gives the total (architecture, <i>Values</i>, the logging list).
   */
  @Test
  default void missedValuesLogOneLineForABurstAndTheRestAtClose()
      throws InterruptedException {
    String source = "gauge-" + UUID.randomUUID().toString().substring(0, 8);
    int retention = 4;
    List<String> lines;
    try (CapturedStderr err = new CapturedStderr()) {
      try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(retention).build())) {
        EventBlock<Integer> events = new EventBlock<>();
        Reader<Integer> lagging = core.source(source, events).reader();
        core.start();
        for (int burst = 0; burst < 2; burst++) {
          for (int i = 1; i <= retention + 6; i++) {
            events.publish(burst * 100 + i);
          }
          List<Integer> kept = lagging.drain();
          assertEquals(retention, kept.size(), "the reader kept the retention: " + kept);
          assertEquals(burst * 100 + retention + 6, kept.get(kept.size() - 1));
        }
        assertEquals(12, lagging.missed(), "both bursts' misses are counted");
      }
      lines = err.lines();
    }
    List<String> misses =
        lines.stream()
            .filter(l -> l.contains("source '" + source + "'") && l.contains("missed"))
            .toList();
    assertEquals(
        2,
        misses.size(),
        "one line for the first misses, one at close for the rest:\n" + String.join("\n", lines));
    long logged = 0;
    for (String line : misses) {
      assertTrue(line.contains(" WARN "), line);
      Matcher first = MISSED_COUNT.matcher(line);
      long count = first.find() ? Long.parseLong(first.group(1)) : CapturedStderr.summarised(line);
      assertTrue(count > 0, "says how many: " + line);
      logged += count;
    }
    assertEquals(12, logged, "the lines count every missed value:\n" + String.join("\n", misses));
  }

  /** How many values the first line about missed values counts: "missed 6 value(s)". */
  Pattern MISSED_COUNT = Pattern.compile("missed (\\d+) value");
}
