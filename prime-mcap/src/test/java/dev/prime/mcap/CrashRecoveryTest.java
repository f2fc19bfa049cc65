package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.BufferedReader;
import java.io.File;
import java.io.IOException;
import java.io.InputStreamReader;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A recorder JVM killed with SIGKILL while its file is open: the file has no footer, the normal
 * reader says it is unfinished, and {@link McapReader#openUnfinished} recovers every message of
 * the chunks written whole, in order, without a gap.
 */
class CrashRecoveryTest {
  @TempDir Path dir;

  private Path recordAndKill(String name, int count, long chunkSize) throws IOException, InterruptedException {
    return recordAndKill(dir.resolve(name), count, chunkSize);
  }

  /** Runs the recorder, waits for it to report its writes, kills it with SIGKILL. */
  static Path recordAndKill(Path file, int count, long chunkSize) throws IOException, InterruptedException {
    String java = new File(System.getProperty("java.home"), "bin/java").getPath();
    Process recorder = new ProcessBuilder(java, "-cp", System.getProperty("java.class.path"),
        CrashingRecorder.class.getName(), file.toString(), String.valueOf(count), String.valueOf(chunkSize))
        .redirectError(ProcessBuilder.Redirect.INHERIT)
        .start();
    try (BufferedReader out = new BufferedReader(new InputStreamReader(recorder.getInputStream(), StandardCharsets.UTF_8))) {
      assertEquals("WROTE " + count, out.readLine(), "the recorder reports its writes");
      recorder.destroyForcibly(); // SIGKILL: no shutdown hook, no close()
      assertTrue(recorder.waitFor(30, TimeUnit.SECONDS), "the recorder died");
    }
    assertEquals(137, recorder.exitValue(), "killed by SIGKILL");
    return file;
  }

  private static List<Long> sequences(McapReader reader) {
    return reader.messages("ticks", CrashingRecorder.Tick.class)
        .map(TypedMessage::sequence).collect(Collectors.toList());
  }

  @Test
  void everyChunkWrittenBeforeAKillIsRecovered() throws Exception {
    int count = 500;
    Path file = recordAndKill("one-per-chunk.mcap", count, 1); // every message closes its chunk
    McapFormatException e = assertThrows(McapFormatException.class, () -> McapReader.open(file).close());
    assertTrue(e.getMessage().contains("McapReader.openUnfinished"), e.getMessage());
    try (McapReader reader = McapReader.openUnfinished(file)) {
      assertEquals(count, reader.messageCount("ticks"), "not one written message lost");
      List<Long> sequences = sequences(reader);
      for (int i = 0; i < count; i++) {
        assertEquals(i, sequences.get(i));
      }
      assertEquals(Files.size(file), reader.unfinishedAt(), "the file ends with a complete record");
    }
  }

  @Test
  void theOpenChunkIsWhatAKillLoses() throws Exception {
    int count = 2_000;
    Path file = recordAndKill("big-chunks.mcap", count, 8_192);
    try (McapReader reader = McapReader.openUnfinished(file)) {
      long recovered = reader.messageCount("ticks");
      long perChunk = count / reader.statistics().chunkCount();
      assertTrue(reader.statistics().chunkCount() >= 5, "chunks: " + reader.statistics().chunkCount());
      assertTrue(recovered < count && recovered >= count - 2 * perChunk,
          recovered + " of " + count + " recovered; at most the open chunk (about " + perChunk + ") is lost");
      List<Long> sequences = sequences(reader);
      assertEquals(recovered, sequences.size());
      for (int i = 0; i < sequences.size(); i++) {
        assertEquals(i, sequences.get(i), "a prefix of the writes, without a gap");
      }
    }
  }

  /**
   * A recorder killed with SIGKILL while it writes (not after): every message whose write had
   * returned (its chunk written, as the recorder acknowledged on its standard output before the
   * kill) is recovered, in order, without a gap, each message whole; the chunk being written when
   * the kill came is left out, not returned in part.
   */
  @Test
  void aKillWhileWritingLosesNoAcknowledgedMessageAndReturnsNoPartOfOne() throws Exception {
    // small messages (the kill lands between writes) to large ones (it lands in one, likely)
    killWhileWriting(1024, 300);
    killWhileWriting(64 * 1024, 100);
    killWhileWriting(1024 * 1024, 20);
  }

  private void killWhileWriting(int noteLength, int killAfter) throws Exception {
    Path file = dir.resolve("killed-while-writing-" + noteLength + ".mcap");
    long acknowledged = runAndKill(file, noteLength, killAfter, 0);
    try (McapReader reader = McapReader.openUnfinished(file)) {
      long recovered = reader.messageCount("ticks");
      assertTrue(recovered >= acknowledged + 1,
          recovered + " messages recovered, but " + (acknowledged + 1) + " were acknowledged as written");
      List<TypedMessage<CrashingRecorder.Tick>> messages =
          reader.messages("ticks", CrashingRecorder.Tick.class).collect(Collectors.toList());
      assertEquals(recovered, messages.size());
      for (int i = 0; i < messages.size(); i++) {
        TypedMessage<CrashingRecorder.Tick> m = messages.get(i);
        assertEquals(i, m.sequence(), "a prefix of the writes, without a gap");
        assertEquals(new CrashingRecorder.Tick(i, AckingRecorder.note(i, noteLength)), m.value(), "message " + i + " whole");
      }
      assertTrue(reader.unfinishedAt() > 0 && reader.unfinishedAt() <= Files.size(file),
          "where the complete records end: " + reader.unfinishedAt() + " of " + Files.size(file) + " bytes");
      System.out.printf("killed while writing %d-byte notes: %d acknowledged, %d recovered,"
          + " complete records end at %d of %d bytes%n",
          noteLength, acknowledged + 1, recovered, reader.unfinishedAt(), Files.size(file));
    }
  }

  /**
   * Runs an {@link AckingRecorder} on {@code file} (rotated at {@code rotateAtSize}, 0 for none),
   * kills it with SIGKILL once it has acknowledged write {@code killAfter}, and returns the last
   * write it acknowledged before it died.
   */
  private static long runAndKill(Path file, int noteLength, int killAfter, long rotateAtSize) throws Exception {
    String java = new File(System.getProperty("java.home"), "bin/java").getPath();
    Process recorder = new ProcessBuilder(java, "-cp", System.getProperty("java.class.path"),
        AckingRecorder.class.getName(), file.toString(), String.valueOf(noteLength), String.valueOf(rotateAtSize))
        .redirectError(ProcessBuilder.Redirect.INHERIT)
        .start();
    long acknowledged = -1;
    try (BufferedReader out = new BufferedReader(new InputStreamReader(recorder.getInputStream(), StandardCharsets.UTF_8))) {
      String line;
      while (acknowledged < killAfter && (line = out.readLine()) != null) {
        acknowledged = Long.parseLong(line.substring("ACK ".length()));
      }
      assertEquals(killAfter, acknowledged, "the recorder acknowledges its writes one by one");
      // SIGKILL while it goes on writing (through its handle: Process.destroyForcibly would also
      // close the pipe, and with it the acknowledgements still in it)
      assertTrue(recorder.toHandle().destroyForcibly(), "SIGKILL sent");
      assertTrue(recorder.waitFor(30, TimeUnit.SECONDS), "the recorder died");
      // what it acknowledged before it died, still in the pipe
      for (int i = 0; i < 1_000_000 && (line = out.readLine()) != null; i++) {
        acknowledged = Long.parseLong(line.substring("ACK ".length()));
      }
    } finally {
      recorder.destroyForcibly();
    }
    assertEquals(137, recorder.exitValue(), "killed by SIGKILL");
    return acknowledged;
  }

  /**
   * A rotating recorder killed while it writes: its finished files and its last, unfinished one
   * hold every message it acknowledged, in order, without a gap; a merge of them (reading the
   * unfinished one) has them all.
   */
  @Test
  void aRotatedRecordingKilledWhileWritingLosesNoAcknowledgedMessage() throws Exception {
    Path file = dir.resolve("rotated.mcap");
    long acknowledged = runAndKill(file, 1024, 300, 64 * 1024);
    List<Path> files = McapReader.recordingFiles(file);
    assertTrue(files.size() >= 4, "rotated into " + files);
    long next = 0;
    for (Path part : files) {
      try (McapReader reader = McapReader.openUnfinished(part)) {
        for (TypedMessage<CrashingRecorder.Tick> m
            : (Iterable<TypedMessage<CrashingRecorder.Tick>>) reader.messages("ticks", CrashingRecorder.Tick.class)::iterator) {
          assertEquals(next, m.sequence(), part + ": without a gap across files");
          assertEquals(new CrashingRecorder.Tick((int) next, AckingRecorder.note((int) next, 1024)), m.value());
          next++;
        }
      }
    }
    assertTrue(next >= acknowledged + 1, next + " messages recovered, but " + (acknowledged + 1) + " were acknowledged");
    Path merged = dir.resolve("merged.mcap");
    McapMerge.Result result = McapMerge.merge(files, merged, McapMerge.Options.defaults().readUnfinished());
    assertEquals(next, result.messages());
  }

  @Test
  void aFinishedFileReadsTheSameEitherWay() throws IOException {
    Path file = dir.resolve("finished.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(512))) {
      McapChannel<CrashingRecorder.Tick> ticks = writer.channel("ticks", CrashingRecorder.Tick.class);
      for (int i = 0; i < 300; i++) {
        ticks.write(i, i, i, new CrashingRecorder.Tick(i, ""));
      }
    }
    try (McapReader summary = McapReader.open(file); McapReader scan = McapReader.openUnfinished(file)) {
      assertEquals(-1, scan.unfinishedAt());
      assertEquals(summary.statistics().messageCount(), scan.statistics().messageCount());
      assertEquals(summary.statistics().chunkCount(), scan.statistics().chunkCount());
      assertEquals(sequences(summary), sequences(scan));
      assertEquals(summary.metadata(McapWriter.LOSS_METADATA), scan.metadata(McapWriter.LOSS_METADATA));
    }
  }
}
