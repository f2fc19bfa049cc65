package dev.prime.bench;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTimeoutPreemptively;

import java.time.Duration;
import org.junit.jupiter.api.Test;

/**
 * The machine's round-trip baseline echoes every number once and ends its echo thread; its packet
 * variant (the synchronous row's floor) runs the row's adders once a round trip.
 */
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

  @Test
  void theSynchronousRowsFloorRunsTheFourAddersOnThePacketOnceARoundTrip() throws Exception {
    CoreRoundTripBenchmark benchmark = new CoreRoundTripBenchmark();
    CoreRoundTripBenchmark.PacketEcho echo = new CoreRoundTripBenchmark.PacketEcho();
    echo.start();
    try {
      assertTimeoutPreemptively(Duration.ofSeconds(20), () -> {
        // the row's adders add 1, 2, 3 and 4: 10 a round trip, seen by the sender once it is back
        for (long round = 1; round <= 10_000; round++) {
          assertEquals(10 * round, benchmark.roundTripWithPacket(echo), "round " + round);
        }
      });
    } finally {
      echo.stop();
    }
    assertFalse(echo.echoing(), "the echo thread still runs after the trial's end");
  }

  @Test
  void aNumberSentBeforeTheEchoThreadFirstRunsIsStillEchoed() throws Exception {
    CoreRoundTripBenchmark benchmark = new CoreRoundTripBenchmark();
    // JMH sends the first number right after the trial's setup, often before the echo thread has
    // run at all; 500 fresh trials give that race many chances to drop the first number.
    assertTimeoutPreemptively(Duration.ofSeconds(60), () -> {
      for (int trial = 0; trial < 500; trial++) {
        CoreRoundTripBenchmark.Echo echo = new CoreRoundTripBenchmark.Echo();
        echo.start();
        try {
          assertEquals(1, benchmark.roundTrip(echo), "trial " + trial);
          assertEquals(2, benchmark.roundTrip(echo), "trial " + trial);
        } finally {
          echo.stop();
        }
        assertFalse(echo.echoing(), "trial " + trial + ": the echo thread still runs");
      }
    });
  }
}
