package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Recording;
import dev.prime.RecordingOptions;
import dev.prime.Source;
import dev.prime.Tick;
import dev.prime.Tuple2;
import dev.prime.VirtualClock;
import java.time.Duration;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * "Only these two kinds of node are recorded ({@code EventSource}, {@code BlockChain}); no other
 * has a name in the recording: ... timers, combinators ... are not recorded" (architecture,
 * <i>Recording what a controller does</i>), also while they run and publish.
 */
public interface RecordedKindsConformance extends ConformanceBase {

  /**
   * A core recording its event sources, with a timer, a zip, a merge, a combineLatest, a
   * withLatestFrom and a sampler that all publish: the recording names the two event sources only,
   * and asking for a timer or a combinator by its name is refused like any name not recorded.
   */
  @Test
  default void timersAndCombinatorsAreNotRecorded() throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    CoreConfig config =
        CoreConfig.builder().clock(clock).recording(RecordingOptions.ring(100)).build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> left = new EventBlock<>();
      EventBlock<Integer> right = new EventBlock<>();
      Source<Integer> a = core.source("left", left);
      Source<Integer> b = core.source("right", right);
      Source<Tick> beat = core.timer("beat", Duration.ofMillis(10));
      Source<Tuple2<Integer, Integer>> zipped = core.zip(a, b);
      Source<Integer> merged = core.merge(a, b);
      Source<Tuple2<Integer, Integer>> latest = core.combineLatest(a, b);
      Source<Integer> sampled = a.sample(Duration.ofMillis(10));
      Reader<Tick> ticks = beat.reader();
      Reader<Tuple2<Integer, Integer>> pairs = zipped.reader();
      Reader<Integer> all = merged.reader();
      Reader<Tuple2<Integer, Integer>> combined = latest.reader();
      core.start();
      left.publish(1);
      right.publish(2);
      assertEquals(new Tuple2<>(1, 2), takeOrFail(pairs));
      takeOrFail(all, 2);
      takeOrFail(combined);
      clock.advance(Duration.ofMillis(30));
      takeOrFail(ticks, 3);

      Recording recording = core.recording();
      assertEquals(List.of("left", "right"), List.copyOf(recording.names()), "only the event sources");
      for (Source<?> notRecorded : List.of(beat, zipped, merged, latest, sampled)) {
        IllegalArgumentException refused =
            assertThrows(
                IllegalArgumentException.class,
                () -> recording.getAll(notRecorded.name()),
                notRecorded.name());
        assertTrue(refused.getMessage().contains("left"), "lists the recorded names: " + refused);
      }
    }
  }
}
