package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTimeoutPreemptively;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.mcap.internal.Opcode;
import dev.prime.mcap.internal.RecordBuffer;
import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.time.Duration;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A record length is a uint64: a corrupt file may declare one of 2^63 bytes or more (negative as
 * a Java long). The reader refuses it with a {@link McapFormatException} naming the offset,
 * never hangs, never runs out of memory and never throws an unrelated exception.
 */
class DeclaredLengthTest {
  @TempDir Path dir;

  /** 2^64 - 9: with its 9-byte opcode and length prefix, the record's total length wraps to 0. */
  private static final long WRAPS_TO_ZERO = -9L;

  /** A length past 2^63 whose low 32 bits, read as an int, are negative (-16). */
  private static final long PAST_2_TO_63 = 0xFFFF_FFFF_FFFF_FFF0L;

  private static final Duration LIMIT = Duration.ofSeconds(20);

  private static void header(RecordBuffer b) {
    b.raw(Opcode.MAGIC, 0, 8);
    int at = b.beginRecord(Opcode.HEADER);
    b.string("");
    b.string("hand-made");
    b.endRecord(at);
  }

  /** A private record (opcode 0x80, which readers skip) that declares {@code length}. */
  private static long privateRecord(RecordBuffer b, long length) {
    long offset = b.size();
    b.u8(0x80);
    b.u64(length);
    return offset;
  }

  private static void dataEnd(RecordBuffer b) {
    int at = b.beginRecord(Opcode.DATA_END);
    b.u32(0);
    b.endRecord(at);
  }

  private static void footer(RecordBuffer b, long summaryStart) {
    int at = b.beginRecord(Opcode.FOOTER);
    b.u64(summaryStart);
    b.u64(0);
    b.u32(0); // no CRC: 0 means not computed
    b.endRecord(at);
    b.raw(Opcode.MAGIC, 0, 8);
  }

  private static void statistics(RecordBuffer b) {
    int at = b.beginRecord(Opcode.STATISTICS);
    b.u64(0);
    b.u16(0);
    b.u32(0);
    b.u32(0);
    b.u32(0);
    b.u32(0);
    b.u64(0);
    b.u64(0);
    b.u16u64Map(Map.of());
    b.endRecord(at);
  }

  private Path write(String name, RecordBuffer b) throws IOException {
    return Files.write(dir.resolve(name), b.toByteArray());
  }

  /** A file without a summary is read by one pass: a record of 2^64 - 9 bytes must not stall it. */
  @Test
  void aRecordLengthThatWrapsToZeroIsRefusedWhenScanning() throws IOException {
    RecordBuffer b = new RecordBuffer(256);
    header(b);
    long bad = privateRecord(b, WRAPS_TO_ZERO);
    dataEnd(b);
    footer(b, 0);
    Path file = write("wraps.mcap", b);

    McapFormatException e = assertTimeoutPreemptively(LIMIT,
        () -> assertThrows(McapFormatException.class, () -> McapReader.open(file).close()),
        "McapReader.open of a file whose record declares 2^64 - 9 bytes must end");
    assertEquals(bad, e.offset(), e.getMessage());
    assertTrue(e.getMessage().contains("18446744073709551607"), e.getMessage());
  }

  /** {@link McapReader#verify()} looks for the DataEnd by a pass too when it is not right before the summary. */
  @Test
  void verifyRefusesARecordLengthThatWrapsToZero() throws IOException {
    RecordBuffer b = new RecordBuffer(256);
    header(b);
    long bad = privateRecord(b, WRAPS_TO_ZERO);
    dataEnd(b);
    privateRecord(b, 0); // between the DataEnd and the summary: verify() must search for the DataEnd
    long summaryStart = b.size();
    statistics(b);
    footer(b, summaryStart);
    Path file = write("verify.mcap", b);

    try (McapReader reader = McapReader.open(file)) {
      McapFormatException e = assertTimeoutPreemptively(LIMIT,
          () -> assertThrows(McapFormatException.class, reader::verify),
          "verify() of a file whose record declares 2^64 - 9 bytes must end");
      assertEquals(bad, e.offset(), e.getMessage());
    }
  }

  /** An unfinished file's pass stops at such a record, as at any record cut short. */
  @Test
  void anUnfinishedFileStopsAtARecordLongerThanTheFile() throws IOException {
    RecordBuffer b = new RecordBuffer(256);
    header(b);
    long bad = privateRecord(b, Long.MAX_VALUE - 4); // total length overflows a long
    b.raw(new byte[32], 0, 32);
    Path file = write("unfinished.mcap", b);

    try (McapReader reader = assertTimeoutPreemptively(LIMIT, () -> McapReader.openUnfinished(file))) {
      assertEquals(bad, reader.unfinishedAt());
      assertEquals(0, reader.statistics().messageCount());
    }
  }

  /** The summary's CRC is optional (0): a summary record past 2^63 bytes is still refused as malformed. */
  @Test
  void aSummaryRecordPast2To63BytesIsMalformed() throws IOException {
    RecordBuffer b = new RecordBuffer(256);
    header(b);
    dataEnd(b);
    long summaryStart = b.size();
    statistics(b);
    b.u8(Opcode.SCHEMA);
    b.u64(PAST_2_TO_63);
    b.raw(new byte[24], 0, 24);
    footer(b, summaryStart);
    Path file = write("summary.mcap", b);

    McapFormatException e = assertThrows(McapFormatException.class, () -> McapReader.open(file).close());
    assertTrue(e.getMessage().contains("18446744073709551600"), e.getMessage());
  }

  /** Likewise a record inside a chunk whose CRC is 0 (not computed). */
  @Test
  void aChunkRecordPast2To63BytesIsMalformed() throws IOException {
    RecordBuffer records = new RecordBuffer(256);
    int at = records.beginRecord(Opcode.SCHEMA);
    records.u16(1);
    records.string("Reading");
    records.string("jsonschema");
    records.bytes32("{\"type\":\"object\"}".getBytes(StandardCharsets.UTF_8));
    records.endRecord(at);
    at = records.beginRecord(Opcode.CHANNEL);
    records.u16(1);
    records.u16(1);
    records.string("readings");
    records.string("json");
    records.stringMap(Map.of());
    records.endRecord(at);
    records.u8(Opcode.MESSAGE);
    records.u64(PAST_2_TO_63);
    records.raw(new byte[24], 0, 24);

    RecordBuffer b = new RecordBuffer(512);
    header(b);
    at = b.beginRecord(Opcode.CHUNK);
    b.u64(0);
    b.u64(0);
    b.u64(records.size());
    b.u32(0); // no CRC
    b.string("");
    b.u64(records.size());
    b.raw(records.array(), 0, records.size());
    b.endRecord(at);
    dataEnd(b);
    footer(b, 0);
    Path file = write("chunk.mcap", b);

    McapFormatException e = assertThrows(McapFormatException.class, () -> McapReader.open(file).close());
    assertTrue(e.getMessage().contains("18446744073709551600"), e.getMessage());
  }
}
