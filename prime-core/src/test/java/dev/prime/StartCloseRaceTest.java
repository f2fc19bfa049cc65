package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.conformance.ConformanceBase;
import dev.prime.spi.GenericChainCompiler;
import dev.prime.spi.FailureNamingBlock;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/** A core closed while start() is still running must not start its services afterwards. */
class StartCloseRaceTest {

  /** A core whose onStart() pauses until the test lets it go on. */
  private static final class PausingCore extends PrimeCore {
    final CountDownLatch inOnStart = new CountDownLatch(1);
    final CountDownLatch resume = new CountDownLatch(1);

    PausingCore() {
      super("pausing", CoreConfig.defaults());
    }

    @Override
    protected ChainCompiler<?> chainCompiler() {
      return new GenericChainCompiler();
    }

    @Override
    protected void onStart() {
      inOnStart.countDown();
      try {
        resume.await(20, TimeUnit.SECONDS);
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
      }
    }
  }

  @Test
  void servicesStayStoppedWhenCloseOvertakesStart() throws Exception {
    PausingCore core = new PausingCore();
    core.link(core.source(new EventBlock<Integer>()), core.chain(x -> x));
    core.link(core.source(new EventBlock<Integer>()), core.chain(x -> x));
    CompletableFuture<Void> starting = CompletableFuture.runAsync(core::start);
    assertTrue(core.inOnStart.await(20, TimeUnit.SECONDS));
    core.close();
    core.resume.countDown();
    starting.get(20, TimeUnit.SECONDS);
    assertTrue(core.isClosed());
    assertEquals(java.util.List.of(), ConformanceBase.threadsOf(core), "services started after close");
  }
}
