package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;

/** {@link GenericServiceLoop} on its own, as a media uses it. */
class GenericServiceLoopTest {

  /** "Runs once: a second {@link GenericServiceLoop#run()} is refused." */
  @Test
  void aSecondRunIsRefusedAndRunsNothing() {
    AtomicInteger steps = new AtomicInteger();
    GenericService service =
        new GenericService() {
          @Override
          public void initialize() {
            steps.incrementAndGet();
          }

          @Override
          public void work() {
            steps.incrementAndGet();
          }

          @Override
          public void shutdown() {
            steps.incrementAndGet();
          }
        };
    AtomicInteger works = new AtomicInteger();
    // stops after its first work: initialize, work, shutdown
    GenericServiceLoop loop =
        new GenericServiceLoop(
            "driver", service, (name, input, error) -> {}, () -> works.getAndIncrement() >= 2);
    loop.run();
    int ranFirst = steps.get();
    assertEquals(3, ranFirst, "the first run initialized, worked once and shut down");
    IllegalStateException again = assertThrows(IllegalStateException.class, loop::run);
    assertTrue(again.getMessage().contains("'driver' already ran"), again.getMessage());
    assertEquals(ranFirst, steps.get(), "the refused run ran no step");
  }
}
