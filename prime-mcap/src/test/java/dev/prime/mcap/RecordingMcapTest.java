package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.RecordedValue;
import dev.prime.Recording;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.nio.file.Files;
import java.nio.file.Path;
import java.time.Duration;
import java.time.Instant;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** A core's recording written with {@link RecordingMcap} and read back with {@link McapReader}. */
class RecordingMcapTest {
  @TempDir Path dir;

  record Pose(double x, double y) {}

  @Test
  void writesOneChannelPerRecordedNameWithItsValuesTimesAndSequences() throws Exception {
    Path file = dir.resolve("run.mcap");
    CoreConfig config = CoreConfig.builder().recording(RecordingOptions.ring(4)).build();
    try (PrimeCore core = new LibertyCore(config)) {
      EventBlock<Integer> ticks = new EventBlock<>();
      Reader<Pose> poses =
          core.source("ticks", "Wheel ticks", ticks)
              .then(core.chain("odometry", (Integer t) -> new Pose(t, -t)))
              .reader();
      core.chain("unused", (String s) -> s); // recorded, but nothing ran: no channel
      core.start();
      for (int i = 1; i <= 6; i++) {
        ticks.publish(i);
      }
      for (int i = 1; i <= 6; i++) {
        assertTrue(poses.take(Duration.ofSeconds(20)).isPresent());
      }
      Recording recording = core.recording();
      assertEquals(8, RecordingMcap.write(recording, file)); // two rings of 4

      try (McapReader reader = McapReader.open(file)) {
        assertEquals(
            List.of("ticks", "odometry"),
            reader.channels().stream().map(ChannelInfo::topic).toList());
        assertEquals(4, reader.messageCount("ticks"));
        assertEquals(4, reader.messageCount("odometry"));
        ChannelInfo ticksChannel = reader.channel("ticks").orElseThrow();
        assertEquals("Wheel ticks", ticksChannel.metadata().get("prime.pseudoname"));
        assertEquals("2", ticksChannel.metadata().get("prime.dropped"));
        assertEquals("odometry", reader.channel("odometry").orElseThrow().metadata().get("prime.service"));

        List<TypedMessage<Pose>> read = reader.messages("odometry", Pose.class).toList();
        List<RecordedValue<Pose>> recorded = recording.getAllStamped("odometry");
        assertEquals(recorded.stream().map(RecordedValue::value).toList(),
            read.stream().map(TypedMessage::value).toList());
        assertEquals(List.of(2L, 3L, 4L, 5L), read.stream().map(TypedMessage::sequence).toList());
        for (int i = 0; i < read.size(); i++) {
          Instant wall = recorded.get(i).wallTime();
          assertEquals(wall.getEpochSecond() * 1_000_000_000L + wall.getNano(), read.get(i).logTime());
        }
        assertEquals(List.of(3, 4, 5, 6),
            reader.messages("ticks", Integer.class).map(TypedMessage::value).toList());
      }
    }
  }

  @Test
  void aGenericValueNeedsItsTypeGivenAndThenIsWritten() throws Exception {
    CoreConfig config = CoreConfig.builder().recording(RecordingOptions.ring(10)).build();
    try (PrimeCore core = new LibertyCore(config)) {
      var pair = core.chain("pair", (Integer x) -> List.of(x, x + 1)).toBlock();
      core.start();
      pair.process(1);
      Recording recording = core.recording();
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class,
              () -> RecordingMcap.write(recording, dir.resolve("a.mcap")));
      assertTrue(e.getMessage().contains("'pair'") && e.getMessage().contains("types"), e.getMessage());
      assertThrows(IllegalArgumentException.class,
          () -> RecordingMcap.write(recording, dir.resolve("b.mcap"),
              Map.of("nope", ValueType.of(Integer.class))));

      Path file = dir.resolve("c.mcap");
      assertEquals(1, RecordingMcap.write(recording, file,
          Map.of("pair", new ValueType<List<Integer>>() {})));
      try (McapReader reader = McapReader.open(file)) {
        assertEquals(List.of(List.of(1, 2)),
            reader.messages("pair", new ValueType<List<Integer>>() {}).map(TypedMessage::value).toList());
      }
    }
  }

  @Test
  void theFileSaysWhichProcessRecordedItAndKeepsTheCallersMetadata() throws Exception {
    CoreConfig config = CoreConfig.builder().recording(RecordingOptions.ring(10)).build();
    try (PrimeCore core = new LibertyCore(config)) {
      var twice = core.chain("twice", (Integer x) -> 2 * x).toBlock();
      core.start();
      twice.process(21);
      Recording recording = core.recording();
      Path file = dir.resolve("run.mcap");
      RecordingMcap.write(recording, file, Map.of(), Map.of("robot.run", Map.of("goal", "2,1")));

      try (McapReader reader = McapReader.open(file)) {
        List<Map<String, String>> process = reader.metadata(RecordingMcap.PROCESS_METADATA);
        assertEquals(1, process.size());
        String pid = Long.toString(ProcessHandle.current().pid());
        assertEquals(pid, process.get(0).get("pid"));
        assertTrue(!process.get(0).get("host").isBlank(), process.toString());
        assertEquals(pid + "@" + process.get(0).get("host"),
            reader.channel("twice").orElseThrow().metadata().get(RecordingMcap.PROCESS_METADATA));
        assertEquals(List.of(Map.of("goal", "2,1")), reader.metadata("robot.run"));
      }
      IllegalArgumentException reserved = assertThrows(IllegalArgumentException.class,
          () -> RecordingMcap.write(recording, dir.resolve("x.mcap"), Map.of(),
              Map.of(RecordingMcap.PROCESS_METADATA, Map.of())));
      assertTrue(reserved.getMessage().contains("other names"), reserved.getMessage());
      assertThrows(IllegalArgumentException.class,
          () -> RecordingMcap.write(recording, dir.resolve("y.mcap"), Map.of(),
              Map.of(McapWriter.LOSS_METADATA, Map.of())));
    }
  }

  /**
   * A Metadata record name the writer refuses (empty, or its own loss report's) is refused by
   * {@link RecordingMcap#write} and {@link RecordingMcap#stream} before the file at the path is
   * replaced: the recording already there stays.
   */
  @Test
  void aMetadataNameTheWriterRefusesIsRefusedBeforeTheRecordingAtThePathIsReplaced() throws Exception {
    Path file = dir.resolve("run.mcap");
    try (McapWriter earlier = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(earlier.channel("earlier", Integer.class).write(1, 1, 1, 7));
    }
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(4)).build())) {
      EventBlock<Integer> ticks = new EventBlock<>();
      core.source("ticks", ticks);
      core.start();
      ticks.publish(1);
      for (String name : List.of(McapWriter.LOSS_METADATA, "")) {
        Map<String, Map<String, String>> metadata = Map.of(name, Map.of("goal", "2,1"));
        IllegalArgumentException written =
            assertThrows(IllegalArgumentException.class,
                () -> RecordingMcap.write(core.recording(), file, Map.of(), metadata), "write, '" + name + "'");
        assertTrue(written.getMessage().contains("was '" + name + "'"), written.getMessage());
        assertEarlierRecordingStays(file);
        IllegalArgumentException streamed =
            assertThrows(IllegalArgumentException.class,
                () -> RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults(), Map.of(), metadata)
                    .close(),
                "stream, '" + name + "'");
        assertTrue(streamed.getMessage().contains("was '" + name + "'"), streamed.getMessage());
        assertEarlierRecordingStays(file);
      }
    }
  }

  /**
   * What the writer would refuse while writing (a given channel type the recorded values do not
   * fit, a recorded name or pseudoname MCAP's UTF-8 strings cannot hold) is refused by {@link
   * RecordingMcap#write} before the path is touched: the file already there stays, byte for byte.
   */
  @Test
  void whatTheWriterWouldRefuseIsRefusedBeforeTheFileAtThePathIsTouched() throws Exception {
    Path file = dir.resolve("run.mcap");
    try (McapWriter earlier = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(earlier.channel("earlier", Integer.class).write(1, 1, 1, 7));
    }
    byte[] before = Files.readAllBytes(file);
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(4)).build())) {
      EventBlock<Integer> ticks = new EventBlock<>();
      EventBlock<Integer> odd = new EventBlock<>();
      EventBlock<Integer> named = new EventBlock<>();
      core.source("ticks", ticks);
      core.source("odd\uD800", odd);
      core.source("named", "pseudo\uDC00", named);
      core.start();
      ticks.publish(1);

      IllegalArgumentException misfit = assertThrows(IllegalArgumentException.class,
          () -> RecordingMcap.write(core.recording(), file, Map.of("ticks", ValueType.of(Pose.class))));
      assertTrue(misfit.getMessage().contains("'ticks'") && misfit.getMessage().contains(Pose.class.getName()),
          misfit.getMessage());
      assertTrue(Arrays.equals(before, Files.readAllBytes(file)), "the file at the path stays: " + misfit.getMessage());

      odd.publish(2);
      IllegalArgumentException topic =
          assertThrows(IllegalArgumentException.class, () -> RecordingMcap.write(core.recording(), file));
      assertTrue(topic.getMessage().contains("unpaired surrogate"), topic.getMessage());
      assertTrue(Arrays.equals(before, Files.readAllBytes(file)), "the file at the path stays: " + topic.getMessage());
    }
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(4)).build())) {
      EventBlock<Integer> named = new EventBlock<>();
      core.source("named", "pseudo\uDC00", named);
      core.start();
      named.publish(3);
      IllegalArgumentException pseudoname =
          assertThrows(IllegalArgumentException.class, () -> RecordingMcap.write(core.recording(), file));
      assertTrue(pseudoname.getMessage().contains("unpaired surrogate"), pseudoname.getMessage());
      assertTrue(Arrays.equals(before, Files.readAllBytes(file)),
          "the file at the path stays: " + pseudoname.getMessage());
    }
  }

  /**
   * A file holds at most 65535 channels (their ids are 16 bits): a recording with values under
   * more names is refused by {@link RecordingMcap#write} before the path is touched, naming the
   * count and the limit, so the recording already there stays byte for byte.
   */
  @Test
  void moreRecordedNamesThanAFileHoldsAreRefusedBeforeTheFileAtThePathIsTouched() throws Exception {
    Path file = dir.resolve("run.mcap");
    try (McapWriter earlier = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(earlier.channel("earlier", Integer.class).write(1, 1, 1, 7));
    }
    byte[] before = Files.readAllBytes(file);
    int names = 65_536;
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(1)).build())) {
      List<EventBlock<Integer>> events = new ArrayList<>(names);
      for (int i = 0; i < names; i++) {
        EventBlock<Integer> name = new EventBlock<>();
        core.source("n" + i, name);
        events.add(name);
      }
      core.start();
      for (int i = 0; i < names; i++) {
        events.get(i).publish(i);
      }
      assertEquals(names, core.recording().names().size(), "every name is recorded");

      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> RecordingMcap.write(core.recording(), file));
      assertTrue(Arrays.equals(before, Files.readAllBytes(file)), "the file at the path stays: " + e.getMessage());
      assertTrue(e.getMessage().contains("65536") && e.getMessage().contains("65535"), e.getMessage());
    }
  }

  private static void assertEarlierRecordingStays(Path file) throws Exception {
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount("earlier"), "the recording at the path stays");
    }
  }
}
