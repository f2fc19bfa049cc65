package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.ChainFailedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.util.ArrayList;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * A name may hold any character but whitespace, control characters and braces, up to 200 of them
 * (the Javadoc of {@code PrimeCore.chain(String, Block)}): names with path, key and pattern
 * separators, quotes, escapes, letters of other scripts, characters beyond the Basic Multilingual
 * Plane, and names that look like the names Prime derives for links and templates work on every
 * media as any other: a failure names its chain exactly, in a call and to the error handler of a
 * service, and the topology and the services are listed under them.
 */
public interface UnusualNameConformance extends ConformanceBase {

  /** Legal names that a media might mishandle if it used them as more than text. */
  private static List<String> unusualNames() {
    return List.of(
        "odometry/left:wheel",
        "a.b$c;d",
        "a*b?c[d]e\\f",
        "100%s%n",
        "\"quoted\"'single'`back`",
        "größe-θ-名前-مرحبا",
        "robot-\uD83E\uDD16-\uD835\uDC00",
        "a>b",
        "if(x|y)",
        "svc:a:in",
        "x#2",
        "<tag>&amp;",
        "n".repeat(200));
  }

  @Test
  default void unusualButLegalNamesWorkLikeAnyOther() throws InterruptedException {
    List<String> names = unusualNames();
    List<String> reports = new CopyOnWriteArrayList<>();
    CountDownLatch reported = new CountDownLatch(names.size());
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  reports.add(service + " on " + input + ": " + error.getMessage());
                  reported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config);
        PrimeCore calling = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      List<Reader<Integer>> outputs = new ArrayList<>();
      List<Block<Integer, Integer>> calls = new ArrayList<>();
      for (int i = 0; i < names.size(); i++) {
        String name = names.get(i);
        outputs.add(
            core.source("source-" + i, events).then(core.chain(name, failingOnZero(name)))
                .reader());
        calls.add(calling.chain(name, failingOnZero(name)).toBlock());
      }
      Set<String> services = core.serviceNames();
      for (String name : names) {
        assertTrue(services.contains(name), name + " among the services " + services);
      }
      core.start();
      calling.start();
      for (int i = 0; i < names.size(); i++) {
        String name = names.get(i);
        Block<Integer, Integer> call = calls.get(i);
        ChainFailedException e = assertThrows(ChainFailedException.class, () -> call.process(0));
        assertEquals(name, e.chainName());
        assertEquals(name + " failed on 0", e.getCause().getMessage());
        assertEquals(6, call.process(5), name + " goes on");
      }
      events.publish(0);
      events.publish(5);
      for (int i = 0; i < names.size(); i++) {
        assertEquals(6, takeOrFail(outputs.get(i)), names.get(i) + "'s service goes on");
      }
      assertTrue(
          reported.await(patience().toMillis(), TimeUnit.MILLISECONDS),
          "every service's failure reported: " + reports);
      List<String> expected = new ArrayList<>();
      for (String name : names) {
        expected.add(name + " on 0: " + name + " failed on 0");
      }
      assertEquals(expected.stream().sorted().toList(), reports.stream().sorted().toList());
    }
  }

  /** Adds one; fails on 0, saying which chain it is. */
  private static Block<Integer, Integer> failingOnZero(String name) {
    return x -> {
      if (x == 0) {
        throw new IllegalStateException(name + " failed on 0");
      }
      return x + 1;
    };
  }
}
