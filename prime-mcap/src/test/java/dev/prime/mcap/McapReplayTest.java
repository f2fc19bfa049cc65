package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeClock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.nio.file.Path;
import java.time.Duration;
import java.time.Instant;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** {@link McapReplay}: order, pace, errors, and a topology run again on its recorded inputs. */
class McapReplayTest {
  @TempDir Path dir;

  record Pose(double x, double y) {}

  record Heading(double degrees, boolean valid) {}

  /** A clock whose sleep only moves its own time: a replay at recorded speed takes no real time. */
  static final class InstantClock implements PrimeClock {
    long now = 1_000;
    final List<Long> sleeps = new ArrayList<>();

    @Override
    public long nanoTime() {
      return now;
    }

    @Override
    public void sleepNanos(long nanos) {
      sleeps.add(nanos);
      now += nanos;
    }

    @Override
    public Instant now() {
      return Instant.ofEpochSecond(0, now);
    }
  }

  /** Two channels, written out of log-time order, with equal log times in reversed sequence. */
  private Path twoChannels() throws Exception {
    Path file = dir.resolve("two.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous().chunkSize(64))) {
      McapChannel<Pose> poses = writer.channel("poses", Pose.class);
      McapChannel<Integer> ticks = writer.channel("ticks", Integer.class);
      writer.channel("ignored", String.class).write(5, 5, 0, "not fed");
      ticks.write(30, 30, 3, 3);
      poses.write(10, 10, 0, new Pose(0, 0));
      ticks.write(20, 20, 2, 2); // equal log times: by sequence, then in file order
      ticks.write(20, 20, 1, 1);
      poses.write(20, 20, 1, new Pose(1, 1));
      poses.write(50, 50, 2, new Pose(2, 2));
    }
    return file;
  }

  @Test
  void feedsTheNamedChannelsByLogTimeThenSequenceAndCountsThem() throws Exception {
    List<String> fed = new ArrayList<>();
    EventBlock<Pose> poses = new EventBlock<>();
    EventBlock<Integer> ticks = new EventBlock<>();
    poses.subscribe(p -> fed.add("pose " + p.x()));
    ticks.subscribe(t -> fed.add("tick " + t));

    ReplayResult result =
        McapReplay.of(twoChannels())
            .feed("ticks", ticks, Integer.class)
            .feed("poses", poses, Pose.class)
            .run();

    // at log time 20: written tick #2, tick #1, pose #1; fed by sequence, equal ones in file order
    assertEquals(List.of("pose 0.0", "tick 1", "pose 1.0", "tick 2", "tick 3", "pose 2.0"), fed);
    assertEquals(Map.of("ticks", 3L, "poses", 3L), result.fed());
    assertEquals(List.of("ticks", "poses"), List.copyOf(result.fed().keySet()));
    assertEquals(6, result.total());
    assertThrows(IllegalArgumentException.class, () -> result.fed("ignored"));
  }

  @Test
  void atRecordedSpeedWaitsTheRecordedIntervalsOnTheGivenClock() throws Exception {
    InstantClock clock = new InstantClock();
    List<Long> fedAt = new ArrayList<>();
    EventBlock<Pose> poses = new EventBlock<>();
    EventBlock<Integer> ticks = new EventBlock<>();
    poses.subscribe(p -> fedAt.add(clock.now));
    ticks.subscribe(t -> fedAt.add(clock.now));

    McapReplay.of(twoChannels())
        .feed("poses", poses, Pose.class)
        .feed("ticks", ticks, Integer.class)
        .options(ReplayOptions.recordedSpeed(clock))
        .run();

    // log times 10, 20, 20, 20, 30, 50: fed at the start plus (log time - 10)
    assertEquals(List.of(1_000L, 1_010L, 1_010L, 1_010L, 1_020L, 1_040L), fedAt);
    assertEquals(List.of(10L, 10L, 20L), clock.sleeps);
  }

  /**
   * {@link McapReplay#run()}: {@code @throws InterruptedException if interrupted while waiting at
   * recorded speed}; the wait for the next value, an hour on, ends with the interrupt.
   */
  @Test
  void anInterruptEndsTheWaitAtRecordedSpeed() throws Exception {
    Path file = dir.resolve("hour.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Integer> ticks = writer.channel("ticks", Integer.class);
      ticks.write(0, 0, 0, 0);
      ticks.write(Duration.ofHours(1).toNanos(), Duration.ofHours(1).toNanos(), 1, 1);
    }
    EventBlock<Integer> ticks = new EventBlock<>();
    CountDownLatch firstFed = new CountDownLatch(1);
    ticks.subscribe(t -> firstFed.countDown());
    CompletableFuture<Throwable> ended = new CompletableFuture<>();
    Thread replaying = new Thread(() -> {
      try {
        McapReplay.of(file).feed("ticks", ticks, Integer.class).options(ReplayOptions.recordedSpeed()).run();
        ended.complete(null);
      } catch (Throwable t) {
        ended.complete(t);
      }
    }, "replaying");
    replaying.start();
    assertTrue(firstFed.await(30, TimeUnit.SECONDS), "the first value is fed at once");
    long interruptedAt = System.nanoTime();
    replaying.interrupt();
    Throwable thrown = ended.get(30, TimeUnit.SECONDS);
    assertTrue(thrown instanceof InterruptedException, "run() ended with " + thrown);
    assertTrue(System.nanoTime() - interruptedAt < TimeUnit.SECONDS.toNanos(10), "ended by the interrupt");
    replaying.join(TimeUnit.SECONDS.toMillis(30));
    assertFalse(replaying.isAlive());
  }

  @Test
  void atRecordedSpeedASlowCallerIsNotMadeToWait() throws Exception {
    InstantClock clock = new InstantClock();
    EventBlock<Pose> poses = new EventBlock<>();
    poses.subscribe(p -> clock.now += 25); // each value takes longer than the recorded gaps

    try (ReplaySession session =
        McapReplay.of(twoChannels())
            .feed("poses", poses, Pose.class)
            .options(ReplayOptions.recordedSpeed(clock))
            .open()) {
      assertEquals(0, session.feedNext().orElseThrow().sequence());
      assertEquals(new Pose(1, 1), session.feedNext().orElseThrow().value());
      assertEquals(50, session.feedNext().orElseThrow().logTime());
      assertEquals(Optional.empty(), session.feedNext());
      assertEquals(3, session.result().fed("poses"));
    }
    assertEquals(List.of(), clock.sleeps);
  }

  @Test
  void aChannelThatIsNotInTheFileIsRefusedNamingTheFilesChannels() throws Exception {
    Path file = twoChannels();
    McapReplay replay =
        McapReplay.of(file)
            .feed("poses", new EventBlock<Pose>(), Pose.class)
            .feed("odometry", new EventBlock<Pose>(), Pose.class)
            .feed("encoders", new EventBlock<Integer>(), Integer.class);

    IllegalArgumentException e = assertThrows(IllegalArgumentException.class, replay::run);

    assertTrue(e.getMessage().contains("no channel [odometry, encoders]"), e.getMessage());
    assertTrue(e.getMessage().contains("its channels: [poses, ticks, ignored]"), e.getMessage());
  }

  @Test
  void aTypeThatDoesNotDecodeNamesTheChannelAndTheMessage() throws Exception {
    Path file = twoChannels();
    List<Heading> fed = new ArrayList<>();
    EventBlock<Heading> headings = new EventBlock<>();
    headings.subscribe(fed::add);

    IllegalArgumentException e =
        assertThrows(
            IllegalArgumentException.class,
            () -> McapReplay.of(file).feed("poses", headings, Heading.class).run());

    assertTrue(e.getMessage().contains("message 0 of channel 'poses'"), e.getMessage());
    assertTrue(e.getMessage().contains("does not decode as " + ValueType.of(Heading.class).name()), e.getMessage());
    assertEquals(List.of(), fed);
  }

  /**
   * The file of a recorder that was killed has no footer: a replay of it is refused, saying how to
   * make a finished file of its complete chunks, and that file replays.
   */
  @Test
  void anUnfinishedFileIsRefusedSayingHowToReplayWhatItHolds() throws Exception {
    Path whole = dir.resolve("whole.mcap");
    try (McapWriter writer = McapWriter.open(whole, McapWriterOptions.defaults().synchronous().chunkSize(64))) {
      McapChannel<Integer> ticks = writer.channel("ticks", Integer.class);
      for (int i = 0; i < 20; i++) {
        ticks.write(i, i, i, i);
      }
    }
    byte[] bytes = java.nio.file.Files.readAllBytes(whole);
    Path killed = java.nio.file.Files.write(dir.resolve("killed.mcap"), java.util.Arrays.copyOf(bytes, bytes.length / 2));
    List<Integer> fed = new ArrayList<>();
    EventBlock<Integer> ticks = new EventBlock<>();
    ticks.subscribe(fed::add);

    McapFormatException e =
        assertThrows(McapFormatException.class, () -> McapReplay.of(killed).feed("ticks", ticks, Integer.class).run());

    assertTrue(e.getMessage().contains("the writer was not closed"), e.getMessage());
    assertTrue(e.getMessage().contains("McapMerge") && e.getMessage().contains("--unfinished"), e.getMessage());
    assertEquals(List.of(), fed);

    Path finished = dir.resolve("finished.mcap");
    McapMerge.merge(List.of(killed), finished, McapMerge.Options.defaults().readUnfinished());
    assertTrue(McapReplay.of(finished).feed("ticks", ticks, Integer.class).run().fed("ticks") > 0);
    assertEquals(fed.size(), fed.stream().distinct().count(), "each value once: " + fed);
    assertEquals(fed.get(0), 0, "from the first: " + fed);
  }

  @Test
  void nothingNamedOrAChannelNamedTwiceIsRefused() throws Exception {
    Path file = twoChannels();
    IllegalStateException none = assertThrows(IllegalStateException.class, () -> McapReplay.of(file).run());
    assertTrue(none.getMessage().contains("feed(channel"), none.getMessage());
    McapReplay replay = McapReplay.of(file).feed("poses", new EventBlock<Pose>(), Pose.class);
    assertThrows(
        IllegalArgumentException.class, () -> replay.feed("poses", new EventBlock<Pose>(), Pose.class));
  }

  /**
   * A core's recording of a source and a chain, replayed into the source of a fresh core: the
   * chain's outputs are the recorded ones, in order.
   */
  @Test
  void aRecordedSourceReplayedIntoAFreshTopologyGivesTheRecordedOutputs() throws Exception {
    Path file = dir.resolve("run.mcap");
    int n = 50;
    List<Pose> recorded;
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(100)).build())) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Reader<Pose> poses =
          core.source("ticks", ticks).then(core.chain("odometry", new Integrator())).reader();
      core.start();
      for (int i = 0; i < n; i++) {
        ticks.publish(i * i % 7);
        assertTrue(poses.take(Duration.ofSeconds(20)).isPresent());
      }
      recorded = core.recording().getAll("odometry");
      assertEquals(2L * n, RecordingMcap.write(core.recording(), file));
    }

    List<Pose> replayed;
    ReplayResult result;
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(100)).build())) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Reader<Pose> poses =
          core.source("ticks", ticks).then(core.chain("odometry", new Integrator())).reader();
      core.start();
      result = McapReplay.of(file).feed("ticks", ticks, Integer.class).run();
      for (int i = 0; i < n; i++) {
        assertTrue(poses.take(Duration.ofSeconds(20)).isPresent());
      }
      replayed = core.recording().getAll("odometry");
    }

    assertEquals(n, result.fed("ticks"));
    assertEquals(n, recorded.size());
    assertEquals(recorded, replayed);
    assertFalse(recorded.stream().distinct().count() < n / 2, "the outputs vary: " + recorded);
  }

  /** A block with state: its outputs depend on every input before, in order. */
  static final class Integrator implements dev.prime.Block<Integer, Pose> {
    private double x;
    private double y;

    @Override
    public Pose process(Integer tick) {
      x += tick;
      y = y * 0.5 + tick;
      return new Pose(x, y);
    }
  }
}
