package dev.prime.metrics;

import static org.junit.jupiter.api.Assertions.assertDoesNotThrow;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.ChainCompiler;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.spi.GenericChainCompiler;
import io.micrometer.core.instrument.Meter;
import io.micrometer.core.instrument.Measurement;
import io.micrometer.core.instrument.simple.SimpleMeterRegistry;
import java.time.Duration;
import org.junit.jupiter.api.Test;

/**
 * A read of the meters must not fail for a node that went away meanwhile: with a refresh of zero
 * each read takes a snapshot of its node, and the node may stop running here between the
 * binder's look at which nodes run here and its snapshot of the node.
 */
class LostServiceReadTest {

  /**
   * A core of a media that spreads services over processes, as Optimus does: when told, it loses
   * a service to another process right after it next said that it runs it here.
   */
  private static final class LosingCore extends PrimeCore {
    private volatile String losing; // lost once asked about next
    private volatile String lost;

    LosingCore(CoreConfig config) {
      super("losing", config);
    }

    @Override
    protected ChainCompiler<?> chainCompiler() {
      return new GenericChainCompiler();
    }

    @Override
    protected boolean isHostedHere(String service) {
      if (service.equals(lost)) {
        return false;
      }
      if (service.equals(losing)) {
        lost = service; // this answer is the last that says it runs here
      }
      return true;
    }

    void loseAfterNextQuestion(String service) {
      losing = service;
    }
  }

  @Test
  void aServiceLostDuringAReadWithRefreshZeroReadsWithoutFailing() throws Exception {
    CoreConfig config = CoreConfig.builder().name("losing").metrics(true).build();
    SimpleMeterRegistry registry = new SimpleMeterRegistry();
    try (LosingCore core = new LosingCore(config);
        PrimeMetrics binder = PrimeMetrics.of(core, Duration.ZERO)) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source("numbers", events).then(core.chain("double", (Integer x) -> x * 2)).reader();
      binder.bindTo(registry);
      core.start();
      core.loseAfterNextQuestion("double");
      double in =
          assertDoesNotThrow(
              () -> registry.get(PrimeMetrics.VALUES_IN).tag("service", "double").functionCounter().count(),
              "a read of the meters of a service lost while it was read");
      assertTrue(in == 0 || Double.isNaN(in), "0 from before it was lost, or NaN: " + in);
      for (Meter meter : registry.getMeters()) { // a scrape of every meter, the lost one's too
        for (Measurement measurement : assertDoesNotThrow(meter::measure, meter.getId().toString())) {
          measurement.getValue();
        }
      }
      assertEquals(
          Double.NaN,
          registry.get(PrimeMetrics.VALUES_OUT).tag("service", "double").functionCounter().count(),
          "a service lost reads NaN");
    }
  }
}
