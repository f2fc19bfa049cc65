package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.mcap.internal.Opcode;
import java.io.IOException;
import java.nio.ByteBuffer;
import java.nio.ByteOrder;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * What a power cut (or a kill of a machine) can leave: the file was extended for the last chunk,
 * but that chunk's bytes never reached the disk and read back as zeroes. {@link
 * McapReader#openUnfinished} gives back every message before that chunk and says, through {@link
 * McapReader#unfinishedAt()}, that it stopped where the chunk starts.
 */
class PowerCutRecoveryTest {
  @TempDir Path dir;

  record Reading(int value) {}

  private static final int MESSAGES = 20;
  /** A Chunk record's bytes before its records: opcode, length, times, sizes, CRC, compression. */
  private static final int CHUNK_HEADER = 1 + 8 + 8 + 8 + 8 + 4 + 4 + 8;

  /** A finished file of {@link #MESSAGES} messages, one chunk each. */
  private byte[] recording() throws IOException {
    Path finished = dir.resolve("finished.mcap");
    try (McapWriter writer = McapWriter.open(finished, McapWriterOptions.defaults().chunkSize(1).synchronous())) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < MESSAGES; i++) {
        readings.write(i, i, i, new Reading(i));
      }
    }
    return Files.readAllBytes(finished);
  }

  /** The offset and opcode of each record of the data section, up to the first Metadata record. */
  private static List<long[]> dataRecords(byte[] bytes) {
    ByteBuffer b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN);
    List<long[]> records = new ArrayList<>();
    int offset = Opcode.MAGIC.length;
    for (int i = 0; i < 10_000 && offset < bytes.length; i++) {
      int opcode = bytes[offset] & 0xFF;
      if (opcode == Opcode.METADATA || opcode == Opcode.DATA_END) {
        break;
      }
      records.add(new long[] {offset, opcode});
      offset += 1 + 8 + (int) b.getLong(offset + 1);
    }
    return records;
  }

  private static long lastChunkAt(List<long[]> records) {
    long at = -1;
    for (long[] record : records) {
      if (record[1] == Opcode.CHUNK) {
        at = record[0];
      }
    }
    return at;
  }

  /** The end of the data section's last complete record before the Metadata records. */
  private static int completeEnd(byte[] bytes, List<long[]> records) {
    long[] last = records.get(records.size() - 1);
    return (int) last[0] + 1 + 8
        + (int) ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN).getLong((int) last[0] + 1);
  }

  private static List<Long> sequences(McapReader reader) {
    return reader.messages("readings", Reading.class).map(TypedMessage::sequence).collect(Collectors.toList());
  }

  @Test
  void aZeroFilledLastChunkEndsTheRecoveryWithEverythingBeforeIt() throws IOException {
    byte[] bytes = recording();
    List<long[]> records = dataRecords(bytes);
    int chunk = (int) lastChunkAt(records);
    int end = completeEnd(bytes, records);
    int chunkLength = 1 + 8 + (int) ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN).getLong(chunk + 1);
    // zeroes from the chunk's start, after its opcode and length, after its header, in its
    // records, and only its last byte
    for (int written : new int[] {0, 9, CHUNK_HEADER, CHUNK_HEADER + 10, chunkLength - 1}) {
      byte[] cut = Arrays.copyOf(bytes, end);
      Arrays.fill(cut, chunk + written, end, (byte) 0);
      Path file = Files.write(dir.resolve("power-cut-" + written + ".mcap"), cut);
      assertThrows(McapFormatException.class, () -> McapReader.open(file).close(), "no footer");
      try (McapReader reader = McapReader.openUnfinished(file)) {
        assertEquals(MESSAGES - 1, reader.messageCount("readings"), "zeroes from byte " + written + " of the last chunk");
        List<Long> sequences = sequences(reader);
        assertEquals(MESSAGES - 1, sequences.size());
        for (int i = 0; i < sequences.size(); i++) {
          assertEquals(i, sequences.get(i), "every message before the damaged chunk, without a gap");
        }
        assertEquals(chunk, reader.unfinishedAt(), "the recovery stops where the damaged chunk starts");
      }
    }
  }

  /**
   * A chunk of many messages whose tail never reached the disk (zeroes), or was cut off (a kill
   * while it was being written): the messages at its start that are whole are given back too,
   * none in part, and the recovery says it stopped where the last of them ends.
   */
  @Test
  void theWholeMessagesAtTheStartOfADamagedChunkAreGivenBack() throws IOException {
    Path finished = dir.resolve("big-chunks.mcap");
    int count = 200;
    try (McapWriter writer = McapWriter.open(finished, McapWriterOptions.defaults().chunkSize(2048).synchronous())) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < count; i++) {
        readings.write(i, i, i, new Reading(i));
      }
    }
    byte[] bytes = Files.readAllBytes(finished);
    List<long[]> records = dataRecords(bytes);
    int chunk = (int) lastChunkAt(records);
    int end = completeEnd(bytes, records);
    ByteBuffer b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN);
    int chunkEnd = chunk + 1 + 8 + (int) b.getLong(chunk + 1);
    int before = 0; // the messages of the chunks before the last
    for (long[] record : records) {
      if (record[1] == Opcode.CHUNK && record[0] != chunk) {
        before += innerMessages(bytes, (int) record[0], Integer.MAX_VALUE).size();
      }
    }
    List<Integer> inLast = innerMessages(bytes, chunk, Integer.MAX_VALUE);
    assertTrue(inLast.size() >= 10, "the last chunk has many messages: " + inLast.size());
    for (int damage : new int[] {chunk + CHUNK_HEADER + 1, (chunk + chunkEnd) / 2, chunkEnd - 1}) {
      List<Integer> whole = innerMessages(bytes, chunk, damage);
      int expected = before + whole.size();
      long stops = whole.isEmpty() ? chunk : whole.get(whole.size() - 1);
      byte[] zeroed = Arrays.copyOf(bytes, end);
      Arrays.fill(zeroed, damage, end, (byte) 0);
      byte[] cut = Arrays.copyOf(bytes, damage);
      for (byte[] damaged : List.of(zeroed, cut)) {
        String what = (damaged == cut ? "cut" : "zeroes") + " from byte " + (damage - chunk) + " of the last chunk";
        Path file = Files.write(dir.resolve("damaged.mcap"), damaged);
        try (McapReader reader = McapReader.openUnfinished(file)) {
          assertEquals(expected, reader.messageCount("readings"), what);
          List<TypedMessage<Reading>> read = reader.messages("readings", Reading.class).collect(Collectors.toList());
          assertEquals(expected, read.size(), what);
          for (int i = 0; i < read.size(); i++) {
            assertEquals(i, read.get(i).sequence(), what + ": without a gap");
            assertEquals(new Reading(i), read.get(i).value(), what + ": message " + i + " whole");
          }
          assertEquals(stops, reader.unfinishedAt(), what + ": stops where the last whole message ends");
        }
      }
    }
  }

  /**
   * The file offsets where the Message records of the chunk at {@code chunk} end, for those that
   * end by {@code limit}.
   */
  private static List<Integer> innerMessages(byte[] bytes, int chunk, int limit) {
    ByteBuffer b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN);
    int chunkEnd = chunk + 1 + 8 + (int) b.getLong(chunk + 1);
    int at = chunk + CHUNK_HEADER;
    List<Integer> ends = new ArrayList<>();
    for (int i = 0; i < 100_000 && at < chunkEnd; i++) {
      int opcode = bytes[at] & 0xFF;
      int next = at + 1 + 8 + (int) b.getLong(at + 1);
      if (next > limit) {
        break;
      }
      if (opcode == Opcode.MESSAGE) {
        ends.add(next);
      }
      at = next;
    }
    return ends;
  }

  /** Zeroes after the last complete record (the file was extended, nothing written there). */
  @Test
  void zeroesAfterTheLastCompleteRecordLoseNothing() throws IOException {
    byte[] bytes = recording();
    List<long[]> records = dataRecords(bytes);
    int end = completeEnd(bytes, records);
    Path file = Files.write(dir.resolve("extended.mcap"), Arrays.copyOf(Arrays.copyOf(bytes, end), end + 4096));
    try (McapReader reader = McapReader.openUnfinished(file)) {
      assertEquals(MESSAGES, reader.messageCount("readings"));
      assertEquals(MESSAGES, sequences(reader).size());
      assertEquals(end, reader.unfinishedAt());
    }
  }

  /** A merge of such a file (McapMerge --unfinished) has the messages before the damage. */
  @Test
  void aMergeOfAPowerCutFileHasTheMessagesBeforeTheDamage() throws IOException {
    byte[] bytes = recording();
    List<long[]> records = dataRecords(bytes);
    int chunk = (int) lastChunkAt(records);
    int end = completeEnd(bytes, records);
    byte[] cut = Arrays.copyOf(bytes, end);
    Arrays.fill(cut, chunk + CHUNK_HEADER, end, (byte) 0);
    Path file = Files.write(dir.resolve("power-cut.mcap"), cut);
    Path merged = dir.resolve("merged.mcap");
    McapMerge.Result result = McapMerge.merge(List.of(file), merged, McapMerge.Options.defaults().readUnfinished());
    assertEquals(MESSAGES - 1, result.messages());
    try (McapReader reader = McapReader.open(merged)) {
      assertEquals(MESSAGES - 1, reader.messageCount("readings"));
      assertEquals(Long.toString(chunk),
          reader.metadata(McapMerge.INPUT_METADATA).get(0).get("complete_records_end"));
    }
  }
}
