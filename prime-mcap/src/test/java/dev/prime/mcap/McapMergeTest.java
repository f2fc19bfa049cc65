package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Comparator;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.io.TempDir;

/**
 * {@link McapMerge}: the files of two "processes" (two writers whose channels overlap in time and
 * share a topic) joined into one by log time, channels unified by topic and schema, each input's
 * metadata kept; refused inputs; the command line; and the merged file read by the Python
 * {@code mcap} package.
 */
class McapMergeTest {
  @TempDir Path dir;

  record Pose(double x, double y) {}

  record Command(double left, double right) {}

  record OtherPose(String frame) {}

  /** One message as written: topic, log time, sequence, and the input it came from. */
  record Sent(String topic, long logTime, long sequence, int input) {}

  private final List<Sent> sent = new ArrayList<>();

  /**
   * The robot's process: odometry every 10 ms (some with equal times to the worker's, to check
   * the tie-break), and "shared" (also in the worker's file) with the same schema.
   */
  private Path robotFile(int count) throws Exception {
    Path file = dir.resolve("robot.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(512).synchronous())) {
      writer.metadata("prime.process", Map.of("host", "robot-host", "pid", "11"));
      McapChannel<Pose> odometry = writer.channel("odometry", ValueType.of(Pose.class), Map.of("prime.service", "odometry"));
      McapChannel<Long> shared = writer.channel("shared", ValueType.of(Long.class), Map.of("prime.process", "11@robot-host"));
      for (int i = 0; i < count; i++) {
        long time = 1_000_000_000L + 10_000_000L * i;
        odometry.write(time, time, i, new Pose(i, -i));
        sent.add(new Sent("odometry", time, i, 0));
        if (i % 3 == 0) {
          shared.write(time + 1, time + 1, i, (long) i);
          sent.add(new Sent("shared", time + 1, i, 0));
        }
      }
    }
    return file;
  }

  /** The worker's process: the planner's commands every 10 ms, 5 ms later than odometry. */
  private Path workerFile(int count) throws Exception {
    Path file = dir.resolve("worker.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(700).synchronous())) {
      writer.metadata("prime.process", Map.of("host", "worker-host", "pid", "22"));
      McapChannel<Command> planner = writer.channel("planner", Command.class);
      McapChannel<Long> shared = writer.channel("shared", ValueType.of(Long.class), Map.of("prime.process", "22@worker-host", "extra", "x"));
      for (int i = 0; i < count; i++) {
        long time = 1_000_000_000L + 10_000_000L * i + (i % 4 == 0 ? 0 : 5_000_000L);
        planner.write(time, time, i, new Command(i, i * 2));
        sent.add(new Sent("planner", time, i, 1));
        if (i % 5 == 0) {
          shared.write(time + 1, time + 1, 1000 + i, 1000L + i);
          sent.add(new Sent("shared", time + 1, 1000 + i, 1));
        }
      }
    }
    return file;
  }

  private static Map<String, Long> countsOf(List<Sent> messages) {
    Map<String, Long> counts = new TreeMap<>();
    messages.forEach(m -> counts.merge(m.topic(), 1L, Long::sum));
    return counts;
  }

  @Test
  void mergesByLogTimeThenSequenceWithOneChannelPerTopic() throws Exception {
    Path robot = robotFile(300);
    Path worker = workerFile(250);
    Path merged = dir.resolve("merged.mcap");

    McapMerge.Result result = McapMerge.merge(List.of(robot, worker), merged, McapMerge.Options.defaults().chunkSize(1024));

    List<Sent> expected = new ArrayList<>(sent);
    expected.sort(Comparator.comparingLong(Sent::logTime).thenComparingLong(Sent::sequence)
        .thenComparingInt(Sent::input));
    assertEquals(expected.size(), result.messages());
    assertEquals(countsOf(sent), new TreeMap<>(result.messagesByTopic()));
    try (McapReader reader = McapReader.open(merged)) {
      reader.verify();
      assertTrue(reader.hasSummary());
      assertEquals(List.of("odometry", "shared", "planner"), reader.channels().stream().map(ChannelInfo::topic).toList());
      assertEquals(3, reader.schemas().size(), "Pose, Long and Command, the shared Long once");
      assertEquals(300, reader.messageCount("odometry"));
      assertEquals(250, reader.messageCount("planner"));
      assertEquals(100 + 50, reader.messageCount("shared"));
      assertTrue(reader.statistics().chunkCount() > 10, "chunked: " + reader.statistics());
      List<Sent> read = reader.messages()
          .map(m -> new Sent(m.channel().topic(), m.logTime(), m.sequence(), -1))
          .toList();
      assertEquals(expected.stream().map(s -> new Sent(s.topic(), s.logTime(), s.sequence(), -1)).toList(), read);
      // values survive: the first planner command and the worker's shared values
      assertEquals(new Command(0, 0), reader.messages("planner", Command.class).findFirst().orElseThrow().value());
      assertEquals(List.of(0L, 1000L, 3L), reader.messages("shared", Long.class).limit(3).map(TypedMessage::value).toList());
      ChannelInfo shared = reader.channel("shared").orElseThrow();
      assertEquals("11@robot-host", shared.metadata().get("prime.process"), "the first input's value wins");
      assertEquals("x", shared.metadata().get("extra"), "keys only a later input has are added");
      assertEquals(robot + "," + worker, shared.metadata().get(McapMerge.MERGED_FROM));
      assertEquals(robot.toString(), reader.channel("odometry").orElseThrow().metadata().get(McapMerge.MERGED_FROM));
    }
  }

  /**
   * The merge's chunk size takes what the writer's takes ({@link
   * McapWriterOptions#chunkSize(long)}), 1 byte to 1 GiB, and refuses the rest naming the value:
   * the output is written by the same chunk writer.
   */
  @Test
  void theChunkSizeIsOneByteToOneGibAsTheWritersIs() {
    assertEquals(1, McapMerge.Options.defaults().chunkSize(1).chunkSizeBytes());
    assertEquals(1L << 30, McapMerge.Options.defaults().chunkSize(1L << 30).chunkSizeBytes());
    for (long bytes : new long[] {0, (1L << 30) + 1, Long.MAX_VALUE}) {
      IllegalArgumentException refused =
          assertThrows(IllegalArgumentException.class, () -> McapMerge.Options.defaults().chunkSize(bytes));
      assertTrue(refused.getMessage().contains("1 GiB") && refused.getMessage().contains(Long.toString(bytes)),
          refused.getMessage());
    }
  }

  @Test
  void eachInputsMetadataIsKeptWithWhereItCameFrom() throws Exception {
    Path robot = robotFile(20);
    Path worker = workerFile(10);
    Path merged = dir.resolve("merged.mcap");

    McapMerge.merge(List.of(robot, worker), merged);

    try (McapReader reader = McapReader.open(merged)) {
      List<Map<String, String>> processes = reader.metadata("prime.process");
      assertEquals(2, processes.size(), processes.toString());
      assertEquals(Map.of("host", "robot-host", "pid", "11", McapMerge.MERGED_FROM, robot.toString()), processes.get(0));
      assertEquals(Map.of("host", "worker-host", "pid", "22", McapMerge.MERGED_FROM, worker.toString()), processes.get(1));
      List<Map<String, String>> losses = reader.metadata(McapWriter.LOSS_METADATA);
      assertEquals(List.of(robot.toString(), worker.toString()), losses.stream().map(m -> m.get(McapMerge.MERGED_FROM)).toList());
      assertEquals("0", losses.get(1).get("dropped.planner"));
      List<Map<String, String>> inputs = reader.metadata(McapMerge.INPUT_METADATA);
      assertEquals(2, inputs.size());
      assertEquals(robot.toString(), inputs.get(0).get("file"));
      assertEquals("27", inputs.get(0).get("messages")); // 20 odometry + 7 shared
      assertEquals("odometry,shared", inputs.get(0).get("topics"));
      assertEquals("12", inputs.get(1).get("messages")); // 10 planner + 2 shared
      assertEquals(List.of("prime.process", McapWriter.LOSS_METADATA, McapMerge.INPUT_METADATA), reader.metadataNames());
    }
  }

  /**
   * A merge of a merged file keeps the earlier merge's provenance: a channel's {@value
   * McapMerge#MERGED_FROM} lists the files the earlier merge had the topic from, and a Metadata
   * record copied by the earlier merge still names the file it came from.
   */
  @Test
  void mergingAMergedFileKeepsWhereItsChannelsAndMetadataCameFrom() throws Exception {
    Path robot = robotFile(20);
    Path worker = workerFile(10);
    Path first = dir.resolve("first.mcap");
    McapMerge.merge(List.of(robot, worker), first);
    Path late = dir.resolve("late.mcap");
    try (McapWriter writer = McapWriter.open(late, McapWriterOptions.defaults().synchronous())) {
      writer.metadata("prime.process", Map.of("host", "late-host", "pid", "33"));
      writer.channel("shared", ValueType.of(Long.class)).write(5_000_000_000L, 5_000_000_000L, 0, 5L);
    }
    Path again = dir.resolve("again.mcap");

    McapMerge.merge(List.of(first, late), again);

    try (McapReader reader = McapReader.open(again)) {
      assertEquals(robot + "," + worker + "," + late,
          reader.channel("shared").orElseThrow().metadata().get(McapMerge.MERGED_FROM));
      assertEquals(robot.toString(), reader.channel("odometry").orElseThrow().metadata().get(McapMerge.MERGED_FROM));
      assertEquals(worker.toString(), reader.channel("planner").orElseThrow().metadata().get(McapMerge.MERGED_FROM));
      assertEquals(List.of(robot.toString(), worker.toString(), late.toString()),
          reader.metadata("prime.process").stream().map(m -> m.get(McapMerge.MERGED_FROM)).toList());
      List<Map<String, String>> inputs = reader.metadata(McapMerge.INPUT_METADATA);
      assertEquals(List.of(robot.toString(), worker.toString(), first.toString(), late.toString()),
          inputs.stream().map(m -> m.get("file")).toList(), "the earlier merge's input records, then this one's");
      assertEquals(List.of(first.toString(), first.toString()),
          inputs.subList(0, 2).stream().map(m -> m.get(McapMerge.MERGED_FROM)).toList());
    }
  }

  @Test
  void aTopicWithTwoSchemasIsRefusedNamingBothAndNothingIsWritten() throws Exception {
    Path robot = robotFile(5);
    Path other = dir.resolve("other.mcap");
    try (McapWriter writer = McapWriter.open(other, McapWriterOptions.defaults().synchronous())) {
      writer.channel("odometry", OtherPose.class).write(1, 1, 0, new OtherPose("map"));
    }
    Path merged = dir.resolve("merged.mcap");

    IllegalArgumentException refused =
        assertThrows(IllegalArgumentException.class, () -> McapMerge.merge(List.of(robot, other), merged));

    String message = refused.getMessage();
    assertTrue(message.contains("topic 'odometry' has two different schemas"), message);
    assertTrue(message.contains(Pose.class.getName()) && message.contains(OtherPose.class.getName()), message);
    assertTrue(message.contains(robot.toString()) && message.contains(other.toString()), message);
    assertFalse(Files.exists(merged), "refused before the output is created");
  }

  @Test
  void aTopicWithAnotherValueTypeIsRefused() throws Exception {
    Path a = dir.resolve("a.mcap");
    Path b = dir.resolve("b.mcap");
    try (McapWriter writer = McapWriter.open(a, McapWriterOptions.defaults().synchronous())) {
      writer.channel("n", ValueType.of(Integer.class)).write(1, 1, 0, 1);
    }
    try (McapWriter writer = McapWriter.open(b, McapWriterOptions.defaults().synchronous())) {
      writer.channel("n", ValueType.of(Long.class)).write(1, 1, 0, 1L);
    }
    IllegalArgumentException refused =
        assertThrows(IllegalArgumentException.class, () -> McapMerge.merge(List.of(a, b), dir.resolve("m.mcap")));
    assertTrue(refused.getMessage().contains("topic 'n'"), refused.getMessage());
  }

  @Test
  void filesOfTheSameNameFromTwoMachinesStayApart() throws Exception {
    List<Path> inputs = new ArrayList<>();
    for (String host : List.of("host-a", "host-b")) {
      Path file = Files.createDirectories(dir.resolve(host)).resolve("run.mcap");
      try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
        writer.channel("ticks", ValueType.of(Long.class)).write(host.endsWith("a") ? 2 : 1, 0, 0, 7L);
      }
      inputs.add(file);
    }
    Path merged = dir.resolve("merged.mcap");

    McapMerge.merge(inputs, merged);

    try (McapReader reader = McapReader.open(merged)) {
      assertEquals(inputs.get(0) + "," + inputs.get(1),
          reader.channel("ticks").orElseThrow().metadata().get(McapMerge.MERGED_FROM));
      assertEquals(List.of(1L, 2L), reader.messages().map(McapMessage::logTime).toList());
      assertEquals(List.of(inputs.get(0).toString(), inputs.get(1).toString()),
          reader.metadata(McapMerge.INPUT_METADATA).stream().map(m -> m.get("file")).toList());
    }
  }

  /**
   * A recorder JVM killed with SIGKILL leaves a file without footer: the merge refuses it unless
   * asked to read unfinished files, and then merges the messages of its complete chunks.
   */
  @Test
  void aKilledRecordersFileIsMergedForItsCompleteChunksWhenAsked() throws Exception {
    Path killed = CrashRecoveryTest.recordAndKill(dir.resolve("killed.mcap"), 2_000, 8_192);
    Path robot = robotFile(50);
    Path merged = dir.resolve("merged.mcap");

    McapFormatException refused =
        assertThrows(McapFormatException.class, () -> McapMerge.merge(List.of(robot, killed), merged));
    assertTrue(refused.getMessage().contains("killed.mcap") && refused.getMessage().contains("unfinished"),
        refused.getMessage());
    assertFalse(Files.exists(merged));

    long recovered;
    try (McapReader reader = McapReader.openUnfinished(killed)) {
      recovered = reader.messageCount("ticks");
    }
    assertTrue(recovered > 0 && recovered < 2_000, "the open chunk is lost: " + recovered);
    McapMerge.Result result =
        McapMerge.merge(List.of(robot, killed), merged, McapMerge.Options.defaults().readUnfinished());

    assertEquals(recovered, result.messagesByTopic().get("ticks"));
    assertEquals(50 + 17 + recovered, result.messages()); // odometry 50, shared every third
    try (McapReader reader = McapReader.open(merged)) {
      List<Long> sequences = reader.messages("ticks").map(McapMessage::sequence).toList();
      for (int i = 0; i < sequences.size(); i++) {
        assertEquals(i, sequences.get(i), "a prefix of the killed recorder's writes, without a gap");
      }
      List<Map<String, String>> inputs = reader.metadata(McapMerge.INPUT_METADATA);
      assertFalse(inputs.get(0).containsKey("unfinished"), inputs.toString());
      assertEquals("true", inputs.get(1).get("unfinished"));
      assertEquals(Long.toString(Files.size(killed)), inputs.get(1).get("complete_records_end"));
    }
    PrintStream quiet = new PrintStream(new ByteArrayOutputStream(), true, StandardCharsets.UTF_8);
    Path viaCli = dir.resolve("cli.mcap");
    assertEquals(1, McapMerge.run(new String[] {"-o", viaCli.toString(), robot.toString(), killed.toString()}, quiet, quiet));
    assertEquals(0, McapMerge.run(
        new String[] {"--unfinished", "-o", viaCli.toString(), robot.toString(), killed.toString()}, quiet, quiet));
    try (McapReader reader = McapReader.open(viaCli)) {
      assertEquals(recovered, reader.messageCount("ticks"));
    }
  }

  @Test
  void badArgumentsAreRefusedSayingWhy() throws Exception {
    Path robot = robotFile(3);
    Path out = dir.resolve("out.mcap");
    assertTrue(assertThrows(IllegalArgumentException.class, () -> McapMerge.merge(List.of(), out))
        .getMessage().contains("at least one input"));
    assertTrue(assertThrows(IllegalArgumentException.class,
            () -> McapMerge.merge(List.of(robot, dir.resolve(".").resolve("robot.mcap")), out))
        .getMessage().contains("given twice"));
    assertTrue(assertThrows(IllegalArgumentException.class, () -> McapMerge.merge(List.of(robot), robot))
        .getMessage().contains("also an input"));
    long before = Files.size(robot);
    assertEquals(before, Files.size(robot), "the input is untouched");
    Path notMcap = Files.writeString(dir.resolve("notes.txt"), "hello, not MCAP");
    McapFormatException malformed =
        assertThrows(McapFormatException.class, () -> McapMerge.merge(List.of(robot, notMcap), out));
    assertTrue(malformed.getMessage().contains("notes.txt"), malformed.getMessage());
  }

  /**
   * A merge's output is a recording of one file: the rotated files an earlier recording left at
   * the output path are deleted (as a writer opened there deletes them), so that
   * {@link McapReader#recordingFiles} lists the merge alone; an input that is one of them is
   * refused before anything is written or deleted.
   */
  @Test
  void aMergeIntoThePathOfARotatedRecordingReplacesThatRecording() throws Exception {
    Path robot = robotFile(5);
    Path out = dir.resolve("out.mcap");
    try (McapWriter earlier =
        McapWriter.open(out, McapWriterOptions.defaults().synchronous().chunkSize(1).rotateAtSize(1))) {
      McapChannel<Pose> poses = earlier.channel("old", Pose.class);
      for (int i = 0; i < 3; i++) {
        assertTrue(poses.write(i, i, i, new Pose(i, i)));
      }
    }
    List<Path> earlierFiles = McapReader.recordingFiles(out);
    assertTrue(earlierFiles.size() >= 3, "the earlier recording rotated: " + earlierFiles);

    Path rotatedInput = earlierFiles.get(1);
    IllegalArgumentException refused =
        assertThrows(IllegalArgumentException.class, () -> McapMerge.merge(List.of(robot, rotatedInput), out));
    assertTrue(refused.getMessage().contains(rotatedInput.toString())
        && refused.getMessage().contains("another file"), refused.getMessage());
    assertEquals(earlierFiles, McapReader.recordingFiles(out), "a refused merge deletes nothing");

    McapMerge.merge(List.of(robot), out);

    assertEquals(List.of(out), McapReader.recordingFiles(out), "the merge is the recording at out.mcap");
    for (Path file : earlierFiles.subList(1, earlierFiles.size())) {
      assertFalse(Files.exists(file), file + " of the earlier recording is deleted");
    }
    try (McapReader reader = McapReader.open(out)) {
      assertEquals(5, reader.messageCount("odometry"));
      assertFalse(reader.channel("old").isPresent(), "nothing of the earlier recording");
    }
  }

  @Test
  void theCommandLineMergesAndReportsPerTopic() throws Exception {
    Path robot = robotFile(30);
    Path worker = workerFile(20);
    Path out = dir.resolve("cli.mcap");
    ByteArrayOutputStream stdout = new ByteArrayOutputStream();
    ByteArrayOutputStream stderr = new ByteArrayOutputStream();
    PrintStream o = new PrintStream(stdout, true, StandardCharsets.UTF_8);
    PrintStream e = new PrintStream(stderr, true, StandardCharsets.UTF_8);

    assertEquals(0, McapMerge.run(new String[] {"-o", out.toString(), robot.toString(), worker.toString()}, o, e),
        stderr.toString(StandardCharsets.UTF_8));
    assertEquals("merged 64 messages from 2 files into " + out + ": odometry 30, shared 14, planner 20",
        stdout.toString(StandardCharsets.UTF_8).strip());
    try (McapReader reader = McapReader.open(out)) {
      assertEquals(64, reader.statistics().messageCount());
    }

    stdout.reset();
    Path one = dir.resolve("one.mcap");
    try (McapWriter writer = McapWriter.open(one, McapWriterOptions.defaults().synchronous())) {
      writer.channel("planner", Command.class).write(1, 1, 0, new Command(1, 2));
    }
    Path single = dir.resolve("single.mcap");
    assertEquals(0, McapMerge.run(new String[] {"-o", single.toString(), one.toString()}, o, e),
        stderr.toString(StandardCharsets.UTF_8));
    assertTrue(stdout.toString(StandardCharsets.UTF_8).startsWith("merged 1 message from 1 file into " + single + ": "),
        stdout.toString(StandardCharsets.UTF_8));

    assertEquals(2, McapMerge.run(new String[] {robot.toString()}, o, e));
    assertTrue(stderr.toString(StandardCharsets.UTF_8).contains("no output: give -o OUTPUT.mcap"));
    assertEquals(2, McapMerge.run(new String[] {"-o", out.toString(), dir.resolve("none.mcap").toString()}, o, e));
    assertTrue(stderr.toString(StandardCharsets.UTF_8).contains("no file '"));
    assertEquals(1, McapMerge.run(new String[] {"-o", out.toString(), robot.toString(), robot.toString()}, o, e));
    assertTrue(stderr.toString(StandardCharsets.UTF_8).contains("given twice"));
  }

  @Test
  @Timeout(value = 6, unit = TimeUnit.MINUTES) // a first pip install may take minutes
  void pythonMcapReadsTheMergedFile() throws Exception {
    PythonMcapCheck python = PythonMcapCheck.installOrSkip();
    Path merged = dir.resolve("merged.mcap");
    McapMerge.merge(List.of(robotFile(400), workerFile(300)), merged, McapMerge.Options.defaults().chunkSize(2048));

    JsonNode check = python.check(merged, dir);

    Map<String, Long> statistics = new TreeMap<>();
    Map<String, Long> read = new TreeMap<>();
    check.get("channels").properties().forEach(entry -> {
      statistics.put(entry.getKey(), entry.getValue().get("statistics_count").asLong());
      read.put(entry.getKey(), entry.getValue().get("read_count").asLong());
    });
    assertEquals(countsOf(sent), statistics, check.toString());
    assertEquals(countsOf(sent), read);
    assertEquals(sent.size(), check.get("message_count").asLong());
    assertTrue(check.get("log_time_sorted").asBoolean());
    assertTrue(check.get("summary_crc_ok").asBoolean());
    assertEquals(List.of(), new ObjectMapper().convertValue(check.get("schema_errors"), List.class));
    Map<String, Integer> records = new LinkedHashMap<>();
    check.get("stream_records").properties().forEach(entry -> records.put(entry.getKey(), entry.getValue().asInt()));
    assertEquals(2 + 2 + 2, records.get("Metadata"), "each input's process and loss records, and one per input: " + records);
  }
}
