package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.RecordingOptions;
import dev.prime.Source;
import dev.prime.liberty.LibertyCore;
import java.nio.file.Path;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import java.util.Map;
import java.util.Set;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.logging.Handler;
import java.util.logging.Level;
import java.util.logging.LogRecord;
import java.util.logging.Logger;
import java.util.stream.Collectors;
import java.util.stream.LongStream;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * {@link RecordingMcap#stream}: a core's recording written continuously, past what its rings
 * hold, with rotation, counted drops when the disk stalls, and a flush on close.
 */
class McapRecorderTest {
  @TempDir Path dir;

  record Pose(double x, double y) {}

  private static PrimeCore core(int capacity) {
    return new LibertyCore(
        CoreConfig.builder().recording(RecordingOptions.ring(capacity)).build());
  }

  @Test
  void aLongRunWithASmallRingGetsEveryValueIntoTheFile() throws Exception {
    Path file = dir.resolve("long.mcap");
    int published = 5_000;
    try (PrimeCore core = core(4)) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Reader<Pose> poses =
          core.source("ticks", "Wheel ticks", ticks)
              .then(core.chain("odometry", (Integer t) -> new Pose(t, -t)))
              .reader();
      core.start();
      McapRecorder recorder;
      try (McapRecorder r =
          RecordingMcap.stream(
              core.recording(), file, McapWriterOptions.defaults().queue(published * 2 + 10, 1 << 30))) {
        recorder = r;
        for (int i = 0; i < published; i++) {
          ticks.publish(i);
          assertTrue(poses.take(Duration.ofSeconds(20)).isPresent());
        }
      }
      assertEquals(published - 4, core.recording().dropped("ticks")); // the ring kept 4
      assertEquals(0, recorder.droppedCount());
      assertEquals(2L * published, recorder.writtenCount());
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(published, reader.messageCount("ticks"));
      assertEquals(published, reader.messageCount("odometry"));
      assertEquals(
          LongStream.range(0, published).boxed().toList(),
          reader.messages("ticks", Integer.class).map(m -> (long) m.value()).toList());
      assertEquals(
          LongStream.range(0, published).boxed().toList(),
          reader.messages("odometry", Pose.class).map(TypedMessage::sequence).toList());
      assertEquals("Wheel ticks", reader.channel("ticks").orElseThrow().metadata().get("prime.pseudoname"));
      assertEquals(1, reader.metadata(RecordingMcap.PROCESS_METADATA).size());
      assertEquals("0", reader.metadata(McapWriter.LOSS_METADATA).get(0).get("dropped_messages"));
    }
  }

  @Test
  void rotationBySizeGivesSeveralFilesEachReadableWithAllChannels() throws Exception {
    Path file = dir.resolve("rotated.mcap");
    int published = 2_000;
    List<Path> files;
    try (PrimeCore core = core(8)) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Reader<Pose> poses =
          core.source("ticks", ticks).then(core.chain("odometry", (Integer t) -> new Pose(t, t))).reader();
      core.start();
      McapWriterOptions options =
          McapWriterOptions.defaults().chunkSize(4096).rotateAtSize(16 * 1024).queue(10_000, 1 << 30);
      McapRecorder recorder =
          RecordingMcap.stream(core.recording(), file, options, Map.of(), Map.of("run", Map.of("goal", "2,1")));
      for (int i = 0; i < published; i++) {
        ticks.publish(i);
        assertTrue(poses.take(Duration.ofSeconds(20)).isPresent());
      }
      recorder.close();
      files = recorder.files();
      assertEquals(0, recorder.droppedCount());
    }
    assertTrue(files.size() >= 3, "expected several files, got " + files);
    long ticksTotal = 0;
    long posesTotal = 0;
    for (Path part : files) {
      try (McapReader reader = McapReader.open(part)) {
        assertEquals(
            Set.of("ticks", "odometry"),
            reader.channels().stream().map(ChannelInfo::topic).collect(Collectors.toSet()),
            part.toString());
        assertTrue(reader.messageCount("ticks") > 0, part.toString());
        ticksTotal += reader.messageCount("ticks");
        posesTotal += reader.messages("odometry", Pose.class).count();
        assertEquals("2,1", reader.metadata("run").get(0).get("goal"));
      }
    }
    assertEquals(published, ticksTotal);
    assertEquals(published, posesTotal);
  }

  @Test
  void aStalledDiskDropsWithACountAndNeverBlocksThePublisher() throws Exception {
    Path file = dir.resolve("stalled.mcap");
    StallingOutput[] output = new StallingOutput[1];
    int queue = 16;
    int published = 500;
    try (PrimeCore core = core(4)) {
      EventBlock<Integer> ticks = new EventBlock<>();
      core.source("ticks", ticks);
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(
              core.recording(), file,
              McapWriterOptions.defaults().chunkSize(1).queue(queue, 1 << 30), Map.of(), Map.of(),
              path -> output[0] = new StallingOutput(path));
      output[0].stall();
      ticks.publish(-1);
      assertTrue(output[0].awaitBlocked(20), "the writer thread never reached the disk");
      CountDownLatch publisherDone = new CountDownLatch(1);
      Thread publisher =
          new Thread(
              () -> {
                for (int i = 0; i < published; i++) {
                  ticks.publish(i);
                }
                publisherDone.countDown();
              });
      publisher.start();
      assertTrue(publisherDone.await(20, TimeUnit.SECONDS), "the publisher was stalled by the disk");
      long dropped = recorder.droppedCount();
      assertTrue(dropped >= published - queue, "dropped " + dropped);
      assertEquals(published + 1, recorder.writtenCount() + dropped);
      output[0].release();
      List<String> warnings;
      try (RecorderWarnings logged = new RecorderWarnings()) {
        recorder.close();
        warnings = logged.lines();
      }
      assertEquals(1, warnings.size(), "the WARNING line of the close: " + warnings);
      assertTrue(warnings.get(0).contains("dropped " + dropped + " (the writer could not keep up"),
          warnings.get(0));
      try (McapReader reader = McapReader.open(file)) {
        assertEquals(published + 1 - dropped, reader.messageCount("ticks"));
        Map<String, String> loss = reader.metadata(McapWriter.LOSS_METADATA).get(0);
        assertEquals(Long.toString(dropped), loss.get("dropped_messages"));
        assertEquals(Long.toString(dropped), loss.get("dropped.ticks"));
      }
    }
  }

  @Test
  void closeFlushesWhatIsQueuedAndStopsRecording() throws Exception {
    Path file = dir.resolve("flush.mcap");
    try (PrimeCore core = core(2)) {
      EventBlock<String> words = new EventBlock<>();
      core.source("words", words);
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults().chunkSize(1 << 20));
      for (int i = 0; i < 100; i++) {
        words.publish("w" + i);
      }
      recorder.close(); // one open chunk, never written before close
      words.publish("after close");
      assertEquals(100, recorder.writtenCount());
      try (McapReader reader = McapReader.open(file)) {
        assertEquals(100, reader.messageCount("words"));
        assertEquals("w99", reader.messages("words", String.class).reduce((a, b) -> b).orElseThrow().value());
      }
    }
  }

  /** A value of a class that is not a record: it has no channel type. */
  static final class Opaque {
    final int n;

    Opaque(int n) {
      this.n = n;
    }
  }

  @Test
  void valuesWithNoChannelTypeAreCountedAndLoggedWithTheFixOthersWritten() throws Exception {
    Path file = dir.resolve("typed.mcap");
    int published = 5;
    List<String> warnings = Collections.synchronizedList(new ArrayList<>());
    Logger log = Logger.getLogger(McapRecorder.class.getName());
    Handler handler =
        new Handler() {
          @Override
          public void publish(LogRecord record) {
            if (record.getLevel() == Level.WARNING) {
              warnings.add(record.getMessage());
            }
          }

          @Override
          public void flush() {}

          @Override
          public void close() {}
        };
    log.addHandler(handler);
    try (PrimeCore core = core(16)) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Source<Integer> source = core.source("ticks", ticks);
      Reader<Opaque> opaque = source.then(core.chain("opaque", (Integer t) -> new Opaque(t))).reader();
      Reader<List<Integer>> lists = source.then(core.chain("lists", (Integer t) -> List.of(t, t))).reader();
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(
              core.recording(), file, McapWriterOptions.defaults(),
              Map.of("lists", new ValueType<List<Integer>>() {}), Map.of());
      try (recorder) {
        for (int i = 0; i < published; i++) {
          ticks.publish(i);
          assertTrue(opaque.take(Duration.ofSeconds(10)).isPresent());
          assertTrue(lists.take(Duration.ofSeconds(10)).isPresent());
        }
        long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(10);
        while (recorder.writtenCount() + recorder.unwritableCount() < 3L * published
            && System.nanoTime() < deadline) {
          Thread.sleep(1); // polling the recorder's counts, bounded by the deadline
        }
        assertEquals(published, recorder.unwritableCount(), "every Opaque value");
        assertEquals(2L * published, recorder.writtenCount(), "ticks and lists");
      }
      assertEquals(1, warnings.size(), warnings.toString());
      String warning = warnings.get(0);
      assertTrue(warning.contains("could not write " + published), warning);
      assertTrue(warning.contains("opaque: values of " + Opaque.class.getName()), warning);
      assertTrue(warning.contains("give its type in RecordingMcap.stream(..., types)"), warning);
    } finally {
      log.removeHandler(handler);
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(Set.of("ticks", "lists"), reader.channels().stream().map(ChannelInfo::topic).collect(Collectors.toSet()));
      assertEquals(
          List.of(List.of(0, 0), List.of(1, 1), List.of(2, 2), List.of(3, 3), List.of(4, 4)),
          reader.messages("lists", new ValueType<List<Integer>>() {}).map(TypedMessage::value).toList());
    }
  }

  /**
   * A value whose message is larger than the writer's queue byte bound could never be queued: the
   * recorder counts it as unwritable (not as dropped), says so in the WARNING line of its close,
   * and writes the values before and after it.
   */
  @Test
  void aValueLargerThanTheQueuesByteBoundIsUnwritableNotDroppedAndTheOthersAreWritten()
      throws Exception {
    Path file = dir.resolve("large.mcap");
    try (PrimeCore core = core(4); RecorderWarnings logged = new RecorderWarnings()) {
      EventBlock<String> words = new EventBlock<>();
      core.source("words", words);
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(
              core.recording(), file, McapWriterOptions.defaults().queue(16, 512));
      try (recorder) {
        words.publish("before");
        words.publish("x".repeat(2_000)); // recorded on this thread (Liberty) before publish returns
        words.publish("after");
        assertEquals(1, recorder.unwritableCount(), "the value larger than the byte bound");
        assertEquals(0, recorder.droppedCount(), "nothing dropped");
        assertEquals(2, recorder.writtenCount(), "the values before and after it");
      }
      List<String> warnings = logged.lines();
      assertEquals(1, warnings.size(), warnings.toString());
      String warning = warnings.get(0);
      assertTrue(warning.contains("dropped 0") && warning.contains("could not write 1"), warning);
      assertTrue(warning.contains("larger than the writer's queue byte bound of 512 bytes"), warning);
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(
          List.of("before", "after"),
          reader.messages("words", String.class).map(TypedMessage::value).toList());
      assertEquals("0", reader.metadata(McapWriter.LOSS_METADATA).get(0).get("dropped_messages"));
    }
  }

  /**
   * Values the recorder could not write are in the file's own loss record ({@code
   * unwritable_messages} in {@value McapWriter#LOSS_METADATA}, next to {@code dropped_messages}),
   * so that a reader of the file alone sees that values are missing.
   */
  @Test
  void valuesTheRecorderCouldNotWriteAreCountedInTheFilesLossRecord() throws Exception {
    Path file = dir.resolve("unwritable.mcap");
    try (PrimeCore core = core(4); RecorderWarnings logged = new RecorderWarnings()) {
      EventBlock<String> words = new EventBlock<>();
      EventBlock<Integer> ticks = new EventBlock<>();
      core.source("words", words);
      Source<Integer> source = core.source("ticks", ticks);
      Reader<Opaque> opaque = source.then(core.chain("opaque", (Integer t) -> new Opaque(t))).reader();
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults().queue(16, 512));
      try (recorder) {
        // recorded on this thread (Liberty) before publish returns
        words.publish("before");
        words.publish("x".repeat(2_000)); // larger than the queue's byte bound
        for (int i = 0; i < 2; i++) {
          ticks.publish(i); // its chain's Opaque value has no channel type
          assertTrue(opaque.take(Duration.ofSeconds(10)).isPresent());
        }
        words.publish("after");
        assertEquals(3, recorder.unwritableCount(), "the large value and the two Opaque values");
        assertEquals(0, recorder.droppedCount());
      }
      assertEquals(1, logged.lines().size(), logged.lines().toString());
    }
    try (McapReader reader = McapReader.open(file)) {
      Map<String, String> loss = reader.metadata(McapWriter.LOSS_METADATA).get(0);
      assertEquals("3", loss.get("unwritable_messages"), "the file says values are missing: " + loss);
      assertEquals("0", loss.get("dropped_messages"), loss.toString());
    }
  }

  /**
   * A file holds at most {@value McapWriter#MAX_CHANNELS} channels: the values of a name recorded
   * past that are unwritable for that reason, which the close's WARNING line gives with what to
   * do, not as values without a channel type (their type is fine); the other names are written.
   */
  @Test
  void theNameAfterTheLastChannelAFileHoldsIsUnwritableForThatReason() throws Exception {
    Path file = dir.resolve("names.mcap");
    int names = McapWriter.MAX_CHANNELS + 1;
    try (PrimeCore core = core(1); RecorderWarnings logged = new RecorderWarnings()) {
      List<EventBlock<Integer>> events = new ArrayList<>(names);
      for (int i = 0; i < names; i++) {
        EventBlock<Integer> name = new EventBlock<>();
        core.source("n" + i, name);
        events.add(name);
      }
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults().queue(names + 10, 1 << 30));
      try (recorder) {
        for (int i = 0; i < names; i++) {
          events.get(i).publish(i); // recorded on this thread (Liberty) before publish returns
        }
        assertEquals(1, recorder.unwritableCount(), "the last name's value");
        assertEquals(names - 1L, recorder.writtenCount(), "one value per channel the file holds");
        assertEquals(0, recorder.droppedCount());
      }
      List<String> warnings = logged.lines();
      assertEquals(1, warnings.size(), warnings.toString());
      String warning = warnings.get(0);
      assertTrue(warning.contains("could not write 1") && warning.contains("n" + (names - 1))
          && warning.contains("at most 65535 channels") && warning.contains("record fewer names"), warning);
      assertFalse(warning.contains("give its type"), "its type is not the cause: " + warning);
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(names - 1, reader.channels().size());
      assertEquals(1, reader.messageCount("n" + (names - 2)));
    }
  }

  /**
   * A name refused a channel (here: recorded past the channel limit) is refused once: its later
   * values are counted as unwritable without defining its channel again (the writer's lock and an
   * exception per value).
   */
  @Test
  void aNameRefusedAChannelIsNotRetriedOnEachValue() throws Exception {
    Path file = dir.resolve("refused.mcap");
    int names = McapWriter.MAX_CHANNELS + 1;
    int later = 100;
    try (PrimeCore core = core(1); RecorderWarnings logged = new RecorderWarnings()) {
      List<EventBlock<Integer>> events = new ArrayList<>(names);
      for (int i = 0; i < names; i++) {
        EventBlock<Integer> name = new EventBlock<>();
        core.source("n" + i, name);
        events.add(name);
      }
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults().queue(names + 10, 1 << 30));
      try (recorder) {
        for (int i = 0; i < names; i++) {
          events.get(i).publish(i); // recorded on this thread (Liberty) before publish returns
        }
        EventBlock<Integer> last = events.get(names - 1);
        for (int i = 0; i < later; i++) {
          last.publish(i);
        }
        assertEquals(1L + later, recorder.unwritableCount(), "every value of the refused name");
        assertEquals(names - 1L, recorder.writtenCount());
        assertEquals(names, recorder.definitionAttempts(), "one channel definition (or refusal) per name");
      }
      String warning = logged.lines().get(0);
      assertTrue(warning.contains("could not write " + (1 + later)) && warning.contains("at most 65535 channels"),
          warning);
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(names - 1, reader.channels().size());
    }
  }

  /** A record whose list fails with an Error as it is read, which the JSON encoder passes on as it is. */
  record Faulty(List<Integer> items) {
    static Faulty of(int n) {
      return new Faulty(new java.util.AbstractList<>() {
        @Override
        public Integer get(int index) {
          throw new AssertionError("a broken list of " + n);
        }

        @Override
        public int size() {
          return 1;
        }
      });
    }
  }

  /**
   * A value whose write fails in a way the recorder did not foresee (here: an Error from a list
   * of its record, which the JSON encoder passes on unwrapped) is counted where the recorder's
   * other unwritable values are: in the file's loss record ({@code unwritable_messages}) as in the
   * WARNING line's "could not write", which agree.
   */
  @Test
  void aValueWhoseWriteFailsIsCountedInTheFileAsInTheWarningLine() throws Exception {
    Path file = dir.resolve("failing.mcap");
    int published = 3;
    String warning;
    try (PrimeCore core = core(4); RecorderWarnings logged = new RecorderWarnings()) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Reader<Faulty> faulty = core.source("ticks", ticks).then(core.chain("faulty", (Integer t) -> Faulty.of(t))).reader();
      core.start();
      McapRecorder recorder = RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults());
      try (recorder) {
        for (int i = 0; i < published; i++) {
          ticks.publish(i); // the chain's value is recorded on this thread (Liberty) before publish returns
          assertTrue(faulty.take(Duration.ofSeconds(10)).isPresent());
        }
      }
      assertEquals(1, logged.lines().size(), logged.lines().toString());
      warning = logged.lines().get(0);
      assertTrue(warning.contains("could not write " + published), warning);
    }
    try (McapReader reader = McapReader.open(file)) {
      Map<String, String> loss = reader.metadata(McapWriter.LOSS_METADATA).get(0);
      assertEquals(String.valueOf(published), loss.get("unwritable_messages"),
          "the file counts what the WARNING line says could not be written (" + warning + "): " + loss);
      assertEquals(published, reader.messageCount("ticks"), "the other values are written");
    }
    assertTrue(warning.contains("a broken list of 0"), "says why: " + warning);
  }

  /**
   * A class with no channel type is looked at once: the refusal is remembered for the class, so
   * its later values (under any name) are counted as unwritable without another look (and the
   * exception each look makes).
   */
  @Test
  void aClassWithNoChannelTypeIsLookedAtOnce() throws Exception {
    Path file = dir.resolve("opaque.mcap");
    int published = 100;
    try (PrimeCore core = core(4); RecorderWarnings logged = new RecorderWarnings()) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Source<Integer> source = core.source("ticks", ticks);
      Reader<Opaque> opaque = source.then(core.chain("opaque", (Integer t) -> new Opaque(t))).reader();
      Reader<Opaque> again = source.then(core.chain("again", (Integer t) -> new Opaque(-t))).reader();
      core.start();
      McapRecorder recorder =
          RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults().queue(published * 2, 1 << 30));
      try (recorder) {
        for (int i = 0; i < published; i++) {
          ticks.publish(i); // the chains' values are recorded on this thread (Liberty) before publish returns
          assertTrue(opaque.take(Duration.ofSeconds(10)).isPresent());
          assertTrue(again.take(Duration.ofSeconds(10)).isPresent());
        }
        assertEquals(2L * published, recorder.unwritableCount(), "every Opaque value");
        assertEquals(published, recorder.writtenCount(), "the ticks");
        assertEquals(2, recorder.typeLookups(), "one look per class: Integer, then Opaque");
      }
      String warning = logged.lines().get(0);
      assertTrue(warning.contains("could not write " + 2 * published)
          && warning.contains(": values of " + Opaque.class.getName() + " have no channel type"), warning);
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(List.of("ticks"), reader.channels().stream().map(ChannelInfo::topic).toList());
    }
  }

  @Test
  void synchronousOptionsAreRefusedWithTheFix() throws Exception {
    try (PrimeCore core = core(2)) {
      IllegalArgumentException e =
          assertThrows(
              IllegalArgumentException.class,
              () -> RecordingMcap.stream(
                  core.recording(), dir.resolve("x.mcap"), McapWriterOptions.defaults().synchronous()));
      assertTrue(e.getMessage().contains("queue"), e.getMessage());
    }
  }

  /** The WARNING lines {@link McapRecorder} logs while this is open. */
  private static final class RecorderWarnings extends Handler implements AutoCloseable {
    private final Logger log = Logger.getLogger(McapRecorder.class.getName());
    private final List<String> lines = Collections.synchronizedList(new ArrayList<>());

    RecorderWarnings() {
      log.addHandler(this);
    }

    /** {@return the lines logged so far} */
    List<String> lines() {
      synchronized (lines) {
        return List.copyOf(lines);
      }
    }

    @Override
    public void publish(LogRecord record) {
      if (record.getLevel() == Level.WARNING) {
        lines.add(record.getMessage());
      }
    }

    @Override
    public void flush() {}

    @Override
    public void close() {
      log.removeHandler(this);
    }
  }
}
