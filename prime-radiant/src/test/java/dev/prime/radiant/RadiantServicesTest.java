package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.radiant.internal.FusedCompiler;
import java.util.ArrayList;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/** Sources and services are PrimeCore's, running fused chains. */
class RadiantServicesTest {

  @Test
  void aLinkedChainOnASourceRunsAsOneFusedService() throws Exception {
    try (RadiantCore core = new RadiantCore()) {
      EventBlock<Integer> sensor = new EventBlock<>();
      Source<Integer> readings = core.source("readings", sensor);
      long classesBeforeLink = FusedCompiler.classesGenerated();
      Source<String> out =
          readings.then(
              core.chain("scale", (Integer x) -> x * 10)
                  .then(core.chain("label", (Integer x) -> x > 15 ? "v" + x : null)));
      Reader<String> reader = out.reader();
      core.start();
      assertEquals(Set.of("scale", "label"), core.serviceNames(), "the diagram's services");
      assertEquals(
          1,
          Thread.getAllStackTraces().keySet().stream()
              .filter(t -> t.isAlive() && t.getName().startsWith("prime-" + core.name() + "-"))
              .count(),
          "the linked chain runs on one service thread");
      for (int i = 1; i <= 3; i++) {
        sensor.publish(i);
      }
      List<String> got =
          CompletableFuture.supplyAsync(
                  () -> {
                    List<String> values = new ArrayList<>();
                    try {
                      values.add(reader.take());
                      values.add(reader.take());
                    } catch (InterruptedException e) {
                      Thread.currentThread().interrupt();
                    }
                    return values;
                  })
              .get(10, TimeUnit.SECONDS);
      assertEquals(List.of("v20", "v30"), got, "null outputs are not published");
      assertEquals(
          1,
          FusedCompiler.classesGenerated() - classesBeforeLink,
          "the linked chain is compiled once, into one class, for all the values it serves");
    }
    assertTrue(
        Thread.getAllStackTraces().keySet().stream()
            .noneMatch(t -> t.isAlive() && t.getName().startsWith("prime-radiant-")),
        "close() leaves no service thread");
  }
}
