package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.time.Duration;
import java.util.List;
import java.util.stream.IntStream;
import org.junit.jupiter.api.Test;

/** {@link GenericService#backoff(int)}'s default, which is the same on every media. */
class GenericServiceBackoffTest {

  /**
   * "The default doubles from 10 ms up to 1 s: 10 ms, 20 ms, 40 ms, ..., 640 ms, 1 s, 1 s, ...",
   * and stays at 1 s however many failures come in a row.
   */
  @Test
  void theDefaultBackOffDoublesFrom10MsUpTo1s() {
    GenericService service = () -> {};
    List<Long> millis =
        IntStream.rangeClosed(1, 13).mapToObj(n -> service.backoff(n).toMillis()).toList();
    assertEquals(
        List.of(10L, 20L, 40L, 80L, 160L, 320L, 640L, 1000L, 1000L, 1000L, 1000L, 1000L, 1000L),
        millis,
        "the back-off after 1 to 13 failures in a row");
    assertEquals(Duration.ofSeconds(1), service.backoff(64), "no overflow past 63 doublings");
    assertEquals(Duration.ofSeconds(1), service.backoff(Integer.MAX_VALUE));
  }
}
