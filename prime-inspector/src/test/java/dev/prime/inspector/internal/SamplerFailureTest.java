package dev.prime.inspector.internal;

import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import java.io.IOException;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.util.Map;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * The sampler goes on after its figures could not be read, whatever the figures threw: a media's
 * gauges written in Kotlin may throw a checked exception no signature declares, and an error
 * such as a {@link NoClassDefFoundError} may pass; a sampler that stopped would leave every page
 * showing its last figures as if they were current.
 */
class SamplerFailureTest {
  /** Throws {@code e} as if it were unchecked, as Kotlin code may. */
  @SuppressWarnings("unchecked")
  private static <E extends Throwable> RuntimeException sneaky(Throwable e) throws E {
    throw (E) e;
  }

  @Test
  void theSamplerGoesOnAfterTheFiguresThrewACheckedExceptionOrAnError() throws Exception {
    CountDownLatch samples = new CountDownLatch(4);
    LiveFigures failing =
        new LiveFigures() {
          @Override
          public Map<String, NodeFigures> sample() {
            samples.countDown();
            long taken = 4 - samples.getCount();
            if (taken == 1) {
              throw sneaky(new IOException("the gauges' Redis went away"));
            }
            if (taken == 2) {
              throw new NoClassDefFoundError("a gauge's class went missing");
            }
            return Map.of();
          }

          @Override
          public String description() {
            return "figures that fail";
          }
        };
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().name("failing").build())) {
      InspectorServer server =
          new InspectorServer(
              core, failing, new InetSocketAddress(InetAddress.getLoopbackAddress(), 0));
      try {
        long waitMillis = 8 * InspectorServer.PERIOD_MILLIS;
        assertTrue(samples.await(waitMillis, TimeUnit.MILLISECONDS),
            "the sampler stopped after a failure: " + (4 - samples.getCount())
                + " samples taken in " + waitMillis + " ms, 4 expected");
      } finally {
        server.close();
      }
    }
  }
}
