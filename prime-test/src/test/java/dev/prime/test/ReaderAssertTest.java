package dev.prime.test;

import static dev.prime.test.Media.LIBERTY;
import static dev.prime.test.Media.OPTIMUS;
import static dev.prime.test.Media.OPTIMUS_SLOW_LINK;
import static dev.prime.test.Media.RADIANT;
import static dev.prime.test.ReaderAssert.assertThat;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.time.Duration;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.function.Executable;
import org.opentest4j.AssertionFailedError;

/**
 * {@link ReaderAssert} on a real source of every media, Optimus also over a slow link, each run with
 * its own core.
 */
class ReaderAssertTest {
  private static final Duration SHORT = Duration.ofMillis(300);
  private static final String AFTER = "after \\d+ ms";

  private EventBlock<Integer> sensor;

  /** A source "numbers" of the core, its reader; the core started. */
  private Reader<Integer> numbers(PrimeCore core) {
    sensor = new EventBlock<>();
    Reader<Integer> reader = core.source("numbers", sensor).reader();
    core.start();
    return reader;
  }

  private void publish(Integer... values) {
    for (Integer value : values) {
      sensor.publish(value);
    }
  }

  private static String failure(Executable step) {
    return assertThrows(AssertionFailedError.class, step).getMessage();
  }

  private static void assertMatches(String regex, String message) {
    assertTrue(message.matches(regex), "message:\n" + message + "\ndoes not match:\n" + regex);
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void everyStepPassesOnWhatTheReaderEmits(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1, 2, 3, 4, 5, 6, 7, 8);

    ReaderAssert<Integer> steps =
        assertThat(reader)
            .emits(1, 2)
            .emitsAll(List.of(3))
            .emitsMatching("an even number", x -> x % 2 == 0)
            .emitsSatisfying(x -> assertEquals(5, x))
            .emitsCount(1)
            .skipsUntil("an 8", x -> x == 8)
            .emitsNothingWithin(SHORT);

    assertEquals(List.of(1, 2, 3, 4, 5, 6, 7, 8), steps.taken());
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void emitsWaitsForValuesPublishedLater(PrimeCore core) throws InterruptedException {
    Reader<Integer> reader = numbers(core);
    Thread publisher = publishingOnAnotherThread(1, 2);

    assertThat(reader).emits(1, 2);
    publisher.join(10_000);
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void anotherValueFailsShowingTheExpectedTheActualTheTimeAndWhatCameBefore(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1, 7);

    AssertionFailedError error =
        assertThrows(AssertionFailedError.class, () -> assertThat(reader).emits(1, 2));

    assertMatches(
        "expected value 2 of \\[1, 2\\], 2, but got 7 " + AFTER
            + " \\(values taken by this assertion: \\[1, 7\\]\\)",
        error.getMessage());
    assertEquals(2, error.getExpected().getValue());
    assertEquals(7, error.getActual().getValue());
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void valuesThatDoNotComeInTimeFailAfterTheTimeoutSayingHowLongItWaited(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1);
    long start = System.nanoTime();

    String message = failure(() -> assertThat(reader).within(SHORT).emits(1, 2));

    long waited = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - start);
    assertMatches(
        "expected value 2 of \\[1, 2\\], 2, within 300 ms but no value came; waited \\d+ ms"
            + " \\(values taken by this assertion: \\[1\\]\\)",
        message);
    assertTrue(waited >= 300 && waited < 300 + 5_000, "waited " + waited + " ms");
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void fewerValuesThanCountedFailAfterTheTimeoutSayingWhichWasMissing(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1);
    long start = System.nanoTime();

    String message = failure(() -> assertThat(reader).within(SHORT).emitsCount(2));

    long waited = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - start);
    assertMatches(
        "expected value 2 of 2 more within 300 ms but no value came; waited \\d+ ms"
            + " \\(values taken by this assertion: \\[1\\]\\)",
        message);
    assertTrue(waited >= 300 && waited < 300 + 5_000, "waited " + waited + " ms");
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void aValueThatDoesNotMatchFailsNamingTheCondition(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(4);

    assertMatches(
        "expected an odd number \\(value 1 taken by this assertion\\) but got 4, which does not"
            + " match, " + AFTER + " \\(values taken by this assertion: \\[4\\]\\)",
        failure(() -> assertThat(reader).emitsMatching("an odd number", x -> x % 2 == 1)));
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void assertionsOnAValueFailWithTheirMessageAndTheValue(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(3);

    String message = failure(() -> assertThat(reader).emitsSatisfying(x -> assertEquals(5, x, "speed")));

    assertMatches(
        "value 3 \\(value 1 taken by this assertion, " + AFTER + "\\) failed: speed ==>"
            + " expected: <5> but was: <3> \\(values taken by this assertion: \\[3\\]\\)",
        message);
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void emitsNothingWithinFailsOnAValueShowingIt(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1, 9);

    assertMatches(
        "expected no value within 300 ms but got 9 " + AFTER
            + " \\(values taken by this assertion: \\[1, 9\\]\\)",
        failure(() -> assertThat(reader).emits(1).emitsNothingWithin(SHORT)));
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void emitsNothingWithinZeroLooksOnlyAtWhatIsThereNow(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(4); // in the reader's reach once publish returns, on every media

    assertMatches(
        "expected no value within 0 ms but got 4 " + AFTER
            + " \\(values taken by this assertion: \\[4\\]\\)",
        failure(() -> assertThat(reader).emitsNothingWithin(Duration.ZERO)));
    long start = System.nanoTime();
    assertThat(reader).emitsNothingWithin(Duration.ZERO);
    long waited = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - start);
    assertTrue(waited < 5_000, "nothing there: it returned after " + waited + " ms");
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void emitsNothingWithinFailsWhenTheReaderCompletes(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    core.close();

    assertMatches(
        "expected no value within 300 ms but the reader completed \\(its core closed\\) "
            + AFTER + "; expect that with completes\\(\\) \\(no value taken before\\)",
        failure(() -> assertThat(reader).emitsNothingWithin(SHORT)));
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void skipsUntilFailsWhenNoValueMatchesInTime(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1, 2);

    assertMatches(
        "expected the goal \\(after 2 values that did not match\\) within 300 ms but no value"
            + " came; waited \\d+ ms \\(values taken by this assertion: \\[1, 2\\]\\)",
        failure(() -> assertThat(reader).within(SHORT).skipsUntil("the goal", x -> x > 2)));
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void completesWhenTheCoreIsClosed(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    core.close();

    assertThat(reader).completes();
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void completesWhenTheCoreIsClosedWhileItWaits(PrimeCore core) throws InterruptedException {
    Reader<Integer> reader = numbers(core);
    CountDownLatch asserting = new CountDownLatch(1);
    Thread closer =
        new Thread(
            () -> {
              try {
                if (asserting.await(10, TimeUnit.SECONDS)) {
                  core.close();
                }
              } catch (InterruptedException e) {
                Thread.currentThread().interrupt();
              }
            });
    closer.start();
    long start = System.nanoTime();
    asserting.countDown();

    assertThat(reader).completes();

    long waited = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - start);
    assertTrue(waited < ReaderAssert.DEFAULT_TIMEOUT.toMillis() / 2, "waited " + waited + " ms");
    closer.join(10_000);
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void completesFailsOnAValueThatCameFirst(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(5);

    assertMatches(
        "expected the reader to complete \\(its core to close\\) but got 5 " + AFTER
            + " \\(values taken by this assertion: \\[5\\]\\)",
        failure(() -> assertThat(reader).completes()));
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void completesFailsWhenTheCoreStaysOpen(PrimeCore core) {
    Reader<Integer> reader = numbers(core);

    assertMatches(
        "expected the reader to complete \\(its core to close\\) within 300 ms but it neither"
            + " completed nor emitted; waited \\d+ ms \\(no value taken before\\)",
        failure(() -> assertThat(reader).within(SHORT).completes()));
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void aValueStepSaysSoWhenTheReaderCompletedInstead(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    core.close();

    assertMatches(
        "expected value 1 but the reader completed \\(its core closed\\) " + AFTER
            + " \\(no value taken before\\)",
        failure(() -> assertThat(reader).emits(1)));
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void completesWhenTheCoreIsClosedThoughValuesWereLeftUnread(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1, 2);
    assertThat(reader).emits(1);
    core.close();

    assertThat(reader).completes();
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void withinZeroCountsOnlyTheValuesAlreadyThere(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    publish(1);
    assertThat(reader).emits(1); // the reader is there and its source delivers
    publish(2);
    long start = System.nanoTime();

    assertThat(reader).within(Duration.ZERO).emits(2);
    assertMatches(
        "expected value 3 within 0 ms but no value came; waited \\d+ ms \\(no value taken before\\)",
        failure(() -> assertThat(reader).within(Duration.ZERO).emits(3)));

    long waited = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - start);
    assertTrue(waited < 5_000, "waited " + waited + " ms");
  }

  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void emitsNothingWithinWaitsAllOfItsTimeWhateverTheTimeout(PrimeCore core) {
    Reader<Integer> reader = numbers(core);
    long start = System.nanoTime();

    assertThat(reader).within(Duration.ZERO).emitsNothingWithin(SHORT);

    long waited = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - start);
    assertTrue(waited >= SHORT.toMillis(), "waited " + waited + " ms");
  }

  /**
   * {@link ReaderAssert#within(Duration)} takes any timeout that is not negative, so one as long
   * as a {@link Duration} holds too: each step waits for its values, and {@link
   * ReaderAssert#emitsNothingWithin(Duration)} fails on a value that comes with an {@link
   * AssertionFailedError}, as they do with any other.
   */
  @PrimeTest(media = {LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK})
  void aTimeoutAsLongAsADurationHoldsWaitsForTheValues(PrimeCore core) throws InterruptedException {
    Reader<Integer> reader = numbers(core);
    Duration longest = Duration.ofSeconds(Long.MAX_VALUE);
    publish(1);
    assertThat(reader).within(longest).emits(1);
    assertThat(reader).within(Duration.ofNanos(Long.MAX_VALUE)).emits(); // nothing expected
    Thread publisher = publishingOnAnotherThread(2, 3);
    assertThat(reader).within(Duration.ofNanos(Long.MAX_VALUE)).emits(2, 3);
    publisher.join(10_000);

    publish(9);
    assertMatches(
        "expected no value within 9223372036854775807 s but got 9 " + AFTER
            + " \\(values taken by this assertion: \\[9\\]\\)",
        failure(() -> assertThat(reader).emitsNothingWithin(longest)));
  }

  @PrimeTest(media = Media.LIBERTY)
  void badArgumentsAreRefusedAtTheCall(PrimeCore core) {
    Reader<Integer> reader = numbers(core);

    assertThrows(NullPointerException.class, () -> assertThat(null));
    assertThrows(IllegalArgumentException.class, () -> assertThat(reader).within(Duration.ofMillis(-1)));
    assertThrows(IllegalArgumentException.class, () -> assertThat(reader).emitsCount(-1));
    ReaderAssert<Integer> steps = assertThat(reader);
    List<Executable> nulls =
        List.of(
            () -> steps.within(null),
            () -> steps.emits((Integer[]) null),
            () -> steps.emitsAll(null),
            () -> steps.emitsMatching(null),
            () -> steps.emitsSatisfying(null),
            () -> steps.skipsUntil("the goal", null),
            () -> steps.emitsNothingWithin(null));
    for (Executable call : nulls) {
      String message = assertThrows(NullPointerException.class, call).getMessage();
      assertTrue(message != null && message.endsWith(" must not be null"), message);
    }
  }

  /**
   * A negative quiet time is refused, as a negative timeout is: {@code emitsNothingWithin} would
   * otherwise wait for nothing and pass, whatever comes a moment later.
   */
  @PrimeTest(media = Media.LIBERTY)
  void aNegativeQuietTimeIsRefusedAtTheCall(PrimeCore core) {
    Reader<Integer> reader = numbers(core);

    IllegalArgumentException refused =
        assertThrows(IllegalArgumentException.class,
            () -> assertThat(reader).emitsNothingWithin(Duration.ofMillis(-100)));
    assertEquals("quiet must be zero or positive, was PT-0.1S", refused.getMessage());
  }

  /**
   * Starts a thread that publishes {@code values} once it runs, while the test thread goes on to
   * wait for them; join it afterwards.
   */
  private Thread publishingOnAnotherThread(Integer... values) {
    CountDownLatch waiting = new CountDownLatch(1);
    Thread publisher =
        new Thread(
            () -> {
              try {
                if (waiting.await(10, TimeUnit.SECONDS)) {
                  publish(values);
                }
              } catch (InterruptedException e) {
                Thread.currentThread().interrupt();
              }
            });
    publisher.start();
    waiting.countDown();
    return publisher;
  }
}
