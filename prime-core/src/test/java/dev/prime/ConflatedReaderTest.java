package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import java.time.Duration;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Deque;
import java.util.List;
import java.util.Optional;
import org.junit.jupiter.api.Test;

/**
 * A conflated reader's take hands out the value it took, also when the drain for newer values
 * after it fails (its source became unreachable, on a media whose sources live elsewhere): the
 * wrapped reader handed that value out already, so throwing would lose it.
 */
class ConflatedReaderTest {

  /** A reader whose drain fails while {@link #failing} is set; values come from a queue. */
  private static final class FlakyReader implements Reader<Integer> {
    final Deque<Integer> values = new ArrayDeque<>();
    boolean failing;

    @Override
    public Integer take() {
      return values.removeFirst();
    }

    @Override
    public Optional<Integer> take(Duration timeout) {
      return Optional.ofNullable(values.pollFirst());
    }

    @Override
    public Optional<Integer> poll() {
      return Optional.ofNullable(values.pollFirst());
    }

    @Override
    public List<Integer> drain() {
      if (failing) {
        throw new PrimeException("the source is unreachable");
      }
      List<Integer> all = new ArrayList<>(values);
      values.clear();
      return all;
    }

    @Override
    public long missed() {
      return 0;
    }

    @Override
    public void close() {}
  }

  @Test
  void aTakeWhoseDrainForNewerValuesFailsReturnsTheValueItTook() throws InterruptedException {
    FlakyReader flaky = new FlakyReader();
    ConflatedReader<Integer> latest = new ConflatedReader<>(flaky);
    flaky.values.add(1);
    flaky.failing = true;
    assertEquals(1, latest.take(), "take()");
    flaky.values.add(2);
    assertEquals(Optional.of(2), latest.take(Duration.ofSeconds(1)), "take(timeout)");
    assertThrows(PrimeException.class, latest::poll, "a poll took nothing: its failure is thrown");
    assertThrows(PrimeException.class, latest::drain, "so is a drain's");
    flaky.failing = false;
    flaky.values.add(3);
    flaky.values.add(4);
    assertEquals(4, latest.take(), "the newest once the source answers again");
  }
}
