package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.mcap.internal.Opcode;
import dev.prime.mcap.internal.RecordBuffer;
import java.io.IOException;
import java.io.RandomAccessFile;
import java.lang.management.ManagementFactory;
import java.nio.ByteBuffer;
import java.nio.ByteOrder;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Arrays;
import java.util.List;
import java.util.Map;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;
import org.junit.jupiter.api.io.TempDir;

/** Malformed files give a McapFormatException that names the file, the offset and the problem. */
class MalformedFileTest {
  @TempDir Path dir;

  record Reading(int index, double value) {}

  private Path goodFile() throws IOException {
    Path file = dir.resolve("good.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(256))) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < 100; i++) {
        readings.write(i, i, i, new Reading(i, i));
      }
    }
    return file;
  }

  private static McapFormatException openFails(Path file) {
    return assertThrows(McapFormatException.class, () -> McapReader.open(file).close());
  }

  private static void flip(Path file, long offset) throws IOException {
    try (RandomAccessFile raf = new RandomAccessFile(file.toFile(), "rw")) {
      raf.seek(offset);
      int b = raf.read();
      raf.seek(offset);
      raf.write(b ^ 0x01);
    }
  }

  private static long footerField(Path file, int field) throws IOException {
    byte[] bytes = Files.readAllBytes(file);
    return ByteBuffer.wrap(bytes, bytes.length - 8 - 29 + 9 + 8 * field, 8).order(ByteOrder.LITTLE_ENDIAN).getLong();
  }

  /**
   * {@link McapReader#open}, {@link McapReader#openUnfinished}, {@link McapReplay#run()} and
   * {@link McapMerge#merge(java.util.List, Path)}: {@code @throws IOException if the file cannot
   * be read}; a directory given for the file is refused so, naming it.
   */
  @Test
  void aDirectoryWhereAFileIsExpectedIsRefusedNamingIt() throws IOException {
    Path folder = Files.createDirectory(dir.resolve("run.mcap"));
    List<Executable> reads =
        List.of(
            () -> McapReader.open(folder).close(),
            () -> McapReader.openUnfinished(folder).close(),
            () -> McapReplay.of(folder).feed("readings", new EventBlock<Reading>(), Reading.class).run(),
            () -> McapMerge.merge(List.of(folder), dir.resolve("merged.mcap")));
    for (Executable read : reads) {
      IOException e = assertThrows(IOException.class, read);
      assertTrue(e.getMessage().contains(folder.toString()) && e.getMessage().contains("directory"),
          e.getMessage());
    }
  }

  @Test
  void notAnMcapFile() throws IOException {
    Path text = Files.writeString(dir.resolve("notes.mcap"), "hello, this is not a recording");
    McapFormatException e = openFails(text);
    assertTrue(e.getMessage().startsWith(text + " at byte 0: not an MCAP file: it starts with 68 65 6C 6C 6F"),
        e.getMessage());
    assertEquals(text, e.path());
    assertEquals(0, e.offset());

    Path empty = Files.write(dir.resolve("empty.mcap"), new byte[0]);
    assertTrue(openFails(empty).getMessage().contains("the file is empty (0 bytes)"));
  }

  @Test
  void anotherMajorVersion() throws IOException {
    Path file = goodFile();
    try (RandomAccessFile raf = new RandomAccessFile(file.toFile(), "rw")) {
      raf.seek(5);
      raf.write('1');
    }
    assertTrue(openFails(file).getMessage().contains("MCAP major version byte 0x31 is not supported"));
  }

  @Test
  void truncatedFilesSaySo() throws IOException {
    Path good = goodFile();
    byte[] bytes = Files.readAllBytes(good);
    for (int length : new int[] {bytes.length - 1, bytes.length - 8, bytes.length / 2, 40, 20, 9, 8, 3}) {
      Path cut = Files.write(dir.resolve("cut-" + length + ".mcap"), Arrays.copyOf(bytes, length));
      McapFormatException e = openFails(cut);
      assertTrue(e.getMessage().contains("truncated"), length + " bytes: " + e.getMessage());
    }
    McapFormatException unfinished = openFails(dir.resolve("cut-" + (bytes.length / 2) + ".mcap"));
    assertTrue(unfinished.getMessage().contains("the writer was not closed"), unfinished.getMessage());
  }

  @Test
  void aCorruptSummaryFailsItsCrcOnOpen() throws IOException {
    Path file = goodFile();
    long summaryStart = footerField(file, 0);
    flip(file, summaryStart + 30);
    McapFormatException e = openFails(file);
    assertTrue(e.getMessage().contains("at byte " + summaryStart + ": bad CRC: the summary section's CRC32"), e.getMessage());
    assertEquals(summaryStart, e.offset());
  }

  @Test
  void aCorruptChunkFailsItsCrcWhenRead() throws IOException {
    Path file = goodFile();
    long firstChunk = 8 + 9 + 4 + 4 + "prime-mcap".length();
    flip(file, firstChunk + 100);
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(100, reader.messageCount("readings"), "the summary is intact");
      McapFormatException e = assertThrows(McapFormatException.class, () -> reader.messages().count());
      assertTrue(e.getMessage().contains("at byte " + firstChunk + ": bad CRC: the chunk's records have CRC32"), e.getMessage());
      McapFormatException whole = assertThrows(McapFormatException.class, reader::verify);
      assertTrue(whole.getMessage().contains("bad CRC: the data section's CRC32"), whole.getMessage());
    }
  }

  @Test
  void verifyChecksTheDataSectionOutsideChunksToo() throws IOException {
    Path file = goodFile();
    try (McapReader reader = McapReader.open(file)) {
      reader.verify();
    }
    flip(file, 8 + 9 + 4 + 4); // the Header's library name: in the data section, in no chunk
    try (McapReader reader = McapReader.open(file)) {
      assertEquals("qrime-mcap", reader.library());
      assertEquals(100, reader.messages().count(), "every chunk is intact");
      McapFormatException e = assertThrows(McapFormatException.class, reader::verify);
      assertTrue(e.getMessage().contains("bad CRC: the data section's CRC32"), e.getMessage());
    }
  }

  @Test
  void aFooterPointingOutsideTheFile() throws IOException {
    Path file = goodFile();
    long footer = Files.size(file) - 8 - 29;
    try (RandomAccessFile raf = new RandomAccessFile(file.toFile(), "rw")) {
      raf.seek(footer + 9);
      raf.write(new byte[] {0, 0, 0, 0, 0, 0, 0, 0x70});
    }
    McapFormatException e = openFails(file);
    assertTrue(e.getMessage().contains("the Footer's summary_start"), e.getMessage());
  }

  /**
   * A Footer whose summary_start is corrupt but still inside the file (here: pointing at the first
   * Chunk, at the start of eight MiB of data) is refused as soon as the record there shows it is
   * no summary: the summary starts right after the DataEnd record, and a Chunk is no summary
   * record. Opening must not first read everything from there to the Footer (up to 2 GiB in a
   * large file) only to find that its CRC does not match.
   */
  @Test
  void aSummaryStartPointingIntoTheDataIsRefusedBeforeTheSummaryIsRead() throws IOException {
    Path file = dir.resolve("large.mcap");
    String padding = "x".repeat(1000);
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Padded> padded = writer.channel("padded", Padded.class);
      for (int i = 0; i < 8192; i++) {
        padded.write(i, i, i, new Padded(i, padding));
      }
    }
    long firstChunk = 8 + 9 + 4 + 4 + "prime-mcap".length();
    long footer = Files.size(file) - 8 - 29;
    try (RandomAccessFile raf = new RandomAccessFile(file.toFile(), "rw")) {
      raf.seek(footer + 9);
      raf.write(ByteBuffer.allocate(8).order(ByteOrder.LITTLE_ENDIAN).putLong(firstChunk).array());
    }
    com.sun.management.ThreadMXBean threads =
        (com.sun.management.ThreadMXBean) ManagementFactory.getThreadMXBean();
    Assumptions.assumeTrue(threads.isThreadAllocatedMemorySupported() && threads.isThreadAllocatedMemoryEnabled());
    long before = threads.getCurrentThreadAllocatedBytes();
    McapFormatException e = openFails(file);
    long allocated = threads.getCurrentThreadAllocatedBytes() - before;
    assertTrue(allocated < (1 << 20), "opening allocated " + allocated + " bytes of a " + Files.size(file)
        + "-byte file to refuse a corrupt summary_start; refused with: " + e.getMessage());
    assertEquals(firstChunk, e.offset(), e.getMessage());
    assertTrue(e.getMessage().contains("summary_start " + firstChunk), e.getMessage());
    assertTrue(e.getMessage().contains("Chunk"), e.getMessage());
  }

  record Padded(int index, String padding) {}

  /** A file as another writer may make it: no chunks, no summary; read by one pass. */
  @Test
  void aFileWithoutSummaryOrChunksIsReadByScanning() throws IOException {
    RecordBuffer b = new RecordBuffer(1024);
    b.raw(Opcode.MAGIC, 0, 8);
    int at = b.beginRecord(Opcode.HEADER);
    b.string("");
    b.string("hand-made");
    b.endRecord(at);
    at = b.beginRecord(Opcode.SCHEMA);
    b.u16(1);
    b.string("Reading");
    b.string("jsonschema");
    b.bytes32("{\"type\":\"object\"}".getBytes(StandardCharsets.UTF_8));
    b.endRecord(at);
    at = b.beginRecord(Opcode.CHANNEL);
    b.u16(3);
    b.u16(1);
    b.string("readings");
    b.string("json");
    b.stringMap(Map.of());
    b.endRecord(at);
    long[] times = {30, 10, 20};
    for (long t : times) {
      at = b.beginRecord(Opcode.MESSAGE);
      b.u16(3);
      b.u32(t);
      b.u64(t);
      b.u64(t);
      byte[] json = ("{\"index\":" + t + ",\"value\":0.5}").getBytes(StandardCharsets.UTF_8);
      b.raw(json, 0, json.length);
      b.endRecord(at);
    }
    at = b.beginRecord(Opcode.DATA_END);
    b.u32(0);
    b.endRecord(at);
    at = b.beginRecord(Opcode.FOOTER);
    b.u64(0);
    b.u64(0);
    b.u32(0);
    b.endRecord(at);
    b.raw(Opcode.MAGIC, 0, 8);
    Path file = Files.write(dir.resolve("plain.mcap"), b.toByteArray());

    try (McapReader reader = McapReader.open(file)) {
      assertFalse(reader.hasSummary());
      assertEquals("hand-made", reader.library());
      assertEquals(3, reader.messageCount("readings"));
      assertEquals(3, reader.statistics().messageCount());
      assertEquals(10, reader.statistics().messageStartTime());
      assertEquals(30, reader.statistics().messageEndTime());
      List<Integer> indexes = reader.messages("readings", Reading.class)
          .map(m -> m.value().index()).collect(Collectors.toList());
      assertEquals(List.of(10, 20, 30), indexes, "log-time order");
      reader.verify();
    }
  }

  @Test
  void compressedChunksAreRefusedSayingHowToReadThem() throws IOException {
    RecordBuffer b = new RecordBuffer(256);
    b.raw(Opcode.MAGIC, 0, 8);
    int at = b.beginRecord(Opcode.HEADER);
    b.string("");
    b.string("");
    b.endRecord(at);
    long chunkAt = b.size();
    at = b.beginRecord(Opcode.CHUNK);
    b.u64(0);
    b.u64(0);
    b.u64(40);
    b.u32(0);
    b.string("zstd");
    b.u64(5);
    b.raw(new byte[] {1, 2, 3, 4, 5}, 0, 5);
    b.endRecord(at);
    at = b.beginRecord(Opcode.DATA_END);
    b.u32(0);
    b.endRecord(at);
    at = b.beginRecord(Opcode.FOOTER);
    b.u64(0);
    b.u64(0);
    b.u32(0);
    b.endRecord(at);
    b.raw(Opcode.MAGIC, 0, 8);
    Path file = Files.write(dir.resolve("zstd.mcap"), b.toByteArray());
    McapFormatException e = openFails(file);
    assertTrue(e.getMessage().contains("at byte " + chunkAt + ": the chunk is compressed with 'zstd'"), e.getMessage());
    assertTrue(e.getMessage().contains("mcap decompress"), e.getMessage());
  }

  @Test
  void aMessageOnAnUndefinedChannel() throws IOException {
    RecordBuffer b = new RecordBuffer(256);
    b.raw(Opcode.MAGIC, 0, 8);
    int at = b.beginRecord(Opcode.HEADER);
    b.string("");
    b.string("");
    b.endRecord(at);
    long messageAt = b.size();
    at = b.beginRecord(Opcode.MESSAGE);
    b.u16(9);
    b.u32(0);
    b.u64(0);
    b.u64(0);
    b.endRecord(at);
    at = b.beginRecord(Opcode.DATA_END);
    b.u32(0);
    b.endRecord(at);
    at = b.beginRecord(Opcode.FOOTER);
    b.u64(0);
    b.u64(0);
    b.u32(0);
    b.endRecord(at);
    b.raw(Opcode.MAGIC, 0, 8);
    Path file = Files.write(dir.resolve("orphan.mcap"), b.toByteArray());
    McapFormatException e = openFails(file);
    assertTrue(e.getMessage().contains("at byte " + (messageAt + 9) + ": a Message refers to channel 9"), e.getMessage());
  }
}
