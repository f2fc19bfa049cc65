package dev.prime.bench;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTimeoutPreemptively;

import java.time.Duration;
import org.junit.jupiter.api.Test;

/** The machine's round-trip baseline echoes every number once and ends its echo thread. */
class CoreRoundTripBenchmarkTest {

  @Test
  void everyRoundTripComesBackWithItsOwnNumberAndTheEchoThreadEnds() throws Exception {
    CoreRoundTripBenchmark benchmark = new CoreRoundTripBenchmark();
    CoreRoundTripBenchmark.Echo echo = new CoreRoundTripBenchmark.Echo();
    echo.start();
    try {
      assertTimeoutPreemptively(Duration.ofSeconds(20), () -> {
        for (long expected = 1; expected <= 10_000; expected++) {
          assertEquals(expected, benchmark.roundTrip(echo));
        }
      });
    } finally {
      echo.stop();
    }
    assertFalse(echo.echoing(), "the echo thread still runs after the trial's end");
  }
}
