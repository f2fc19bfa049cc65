package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import java.nio.ByteBuffer;
import java.nio.ByteOrder;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Arrays;
import java.util.List;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A writer stopped while it wrote the summary (after the DataEnd, before the footer) leaves a file
 * that is not finished: {@link McapReader#openUnfinished} reads every message and says, through
 * {@link McapReader#unfinishedAt()}, where its complete records end, as for a file cut anywhere
 * else, and a merge of it says {@code unfinished=true}.
 */
class CutInSummaryTest {
  @TempDir Path dir;

  record Reading(int value) {}

  @Test
  void aFileCutInItsSummaryIsReportedUnfinished() throws Exception {
    Path finished = dir.resolve("finished.mcap");
    try (McapWriter writer = McapWriter.open(finished, McapWriterOptions.defaults().chunkSize(256).synchronous())) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < 50; i++) {
        readings.write(i, i, i, new Reading(i));
      }
    }
    byte[] bytes = Files.readAllBytes(finished);
    long summaryStart = ByteBuffer.wrap(bytes, bytes.length - 8 - 20, 8).order(ByteOrder.LITTLE_ENDIAN).getLong();
    Path cut = Files.write(dir.resolve("cut.mcap"), Arrays.copyOf(bytes, (int) summaryStart + 40));

    assertThrows(McapFormatException.class, () -> McapReader.open(cut).close(), "no footer");
    try (McapReader reader = McapReader.openUnfinished(cut)) {
      assertEquals(50, reader.messageCount("readings"), "every message is before the DataEnd");
      assertEquals(summaryStart, reader.unfinishedAt(), "the complete records end with the DataEnd");
    }

    Path merged = dir.resolve("merged.mcap");
    McapMerge.merge(List.of(cut), merged, McapMerge.Options.defaults().readUnfinished());
    try (McapReader reader = McapReader.open(merged)) {
      Map<String, String> input = reader.metadata(McapMerge.INPUT_METADATA).get(0);
      assertEquals("true", input.get("unfinished"), input.toString());
      assertEquals(Long.toString(summaryStart), input.get("complete_records_end"));
    }
  }
}
