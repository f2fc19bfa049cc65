package dev.prime.mcap;

import dev.prime.mcap.internal.Opcode;
import dev.prime.mcap.internal.RecordCursor;
import java.io.Closeable;
import java.io.IOException;
import java.io.UncheckedIOException;
import java.nio.ByteBuffer;
import java.nio.channels.FileChannel;
import java.nio.file.FileSystemException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.StandardOpenOption;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.Collections;
import java.util.Comparator;
import java.util.Iterator;
import java.util.LinkedHashSet;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.Optional;
import java.util.Set;
import java.util.SortedMap;
import java.util.Spliterator;
import java.util.Spliterators;
import java.util.TreeMap;
import java.util.function.IntPredicate;
import java.util.stream.Collectors;
import java.util.stream.Stream;
import java.util.stream.StreamSupport;
import java.util.zip.CRC32;

/**
 * Reads an MCAP file (mcap.dev). Opening reads only the start, the footer and the summary
 * section: channels, schemas and statistics (message counts per channel) come without reading
 * the data section. Messages are read chunk by chunk through the chunk indexes, merged into
 * log-time order (a chunk is loaded once the merge reaches its start time), and a single
 * topic's read skips the chunks that have none of its messages.
 *
 * <p>A file with no summary (another writer's, written without one) is indexed by one linear
 * pass over its data section when opened, and then read the same way; messages outside chunks
 * are read too. Only uncompressed chunks are read; zstd and lz4 chunks are refused with a
 * clear message.
 *
 * <p>Malformed files give a {@link McapFormatException} naming the file, the byte offset and
 * the problem: not MCAP (bad magic), truncated (no footer or closing magic: the writer did not
 * finish), a bad CRC (summary on open; a chunk when its messages are read; the whole data
 * section in {@link #verify()}), records cut short, a Footer whose summary_start points at no
 * summary (refused before the summary is read). A file whose writer never finished is
 * read with {@link #openUnfinished}. Not thread-safe for concurrent streams.
 */
public final class McapReader implements Closeable {
  private static final int RECORD_PREFIX = 1 + 8;
  private static final int FOOTER_LENGTH = RECORD_PREFIX + 8 + 8 + 4;
  private static final int DATA_END_LENGTH = RECORD_PREFIX + 4;

  private final Path path;
  private final FileChannel file;
  private final long size;
  private String profile = "";
  private String library = "";
  private final Map<Integer, SchemaInfo> schemas = new TreeMap<>();
  private final Map<Integer, ChannelInfo> channels = new TreeMap<>();
  private final List<ChunkRef> chunks = new ArrayList<>();
  private final List<long[]> metadataRecords = new ArrayList<>();
  private McapStatistics statistics;
  private long summaryStart;
  private long recoveredUpTo = -1;
  private boolean summarised;

  private McapReader(Path path, FileChannel file) throws IOException {
    this.path = path;
    this.file = file;
    this.size = file.size();
  }

  /**
   * Opens a file and reads its summary.
   *
   * @param path the file
   * @return the reader
   * @throws IOException if the file cannot be read
   * @throws McapFormatException if it is not a well-formed MCAP file
   * @throws NullPointerException if {@code path} is null
   */
  public static McapReader open(Path path) throws IOException {
    FileChannel file = openFile(path);
    try {
      McapReader reader = new McapReader(path, file);
      reader.readStructure();
      return reader;
    } catch (IOException | RuntimeException e) {
      file.close();
      throw e;
    }
  }

  /**
   * Opens what a writer that never finished left behind (the process was killed, the machine
   * lost power): every complete record of the data section, read in one pass up to the first
   * record that is cut short or damaged (or the DataEnd: a file cut after it, in its summary, has
   * every message, and {@link #unfinishedAt()} is where the DataEnd ends). A damaged record is a
   * Chunk whose CRC or structure does not check, or a Schema, Channel or Message outside chunks
   * that does not parse: what a power cut leaves where the file was extended but the bytes never
   * reached the disk (they read back as zeroes). Of a Chunk cut short, or damaged by such zeroes
   * at its end, the records at its start that end before the cut or the zeroes are read too (the
   * bytes before them are as written), so every whole message before the damage is given back and
   * none in part. {@link #unfinishedAt()} is where the last whole record ends (the damaged
   * record's start if none of it is whole); nothing after it is read. prime-mcap's writer writes
   * each chunk whole as it closes it, so this recovers every message but those of the chunk that
   * was open and those still queued. Statistics are counted in that pass.
   *
   * @param path the file
   * @return the reader
   * @throws IOException if the file cannot be read
   * @throws McapFormatException if it is not MCAP or its Header is malformed
   * @throws NullPointerException if {@code path} is null
   */
  public static McapReader openUnfinished(Path path) throws IOException {
    FileChannel file = openFile(path);
    try {
      McapReader reader = new McapReader(path, file);
      reader.checkLeadingMagic();
      reader.scanDataSection(reader.readHeader(), true);
      return reader;
    } catch (IOException | RuntimeException e) {
      file.close();
      throw e;
    }
  }

  /**
   * Opens a file to read. A directory is refused naming it: it would open, and then fail to read
   * with an IOException saying only "Is a directory".
   */
  private static FileChannel openFile(Path path) throws IOException {
    Objects.requireNonNull(path, "path must not be null: give the MCAP file to read");
    if (Files.isDirectory(path)) {
      throw new FileSystemException(
          path.toString(), null, "a directory, where an MCAP file is expected: give the path of the file");
    }
    return FileChannel.open(path, StandardOpenOption.READ);
  }

  /**
   * The files of a recording that {@link McapWriter} may have rotated: {@code first}, then
   * {@link McapWriter#rotatedPath}{@code (first, 1)}, {@code (first, 2)}, ... as long as they
   * exist: a recording's rotated files are contiguous (a writer rotates into them in order), so
   * the first missing one ends it, and a file further on whose name only looks like a rotated
   * file's (a user's date-named {@code run-2026.mcap} beside {@code run.mcap}) is no file of it
   * and is not listed. Only a file of those names just past the missing one (one of the next
   * two) is taken for the rest of the recording, one of whose files was moved or deleted: that is
   * refused (see below). Open each with {@link #open}. If {@code first} is a symbolic link, the rotated files are
   * those of the file it leads to ({@code runs/run-0001.mcap}... for {@code latest.mcap}, a link to
   * {@code runs/run.mcap}), as a writer opened at the link names them: the recording is the same
   * read through either name.
   *
   * @param first the path the writer was opened with
   * @return the existing files in order (empty if no file of the recording exists)
   * @throws IllegalStateException if a file of the recording is missing while one of the next two
   *     names is there (a file of the recording was moved or deleted): reading on would leave out part of the recording
   *     without a word, so the message names the missing file
   * @throws UncheckedIOException if {@code first} is a symbolic link that leads through more than
   *     40 links (a loop of them), which names no file: the message (that of the {@link
   *     IOException} within) names the path and says to give the recording's first file, or make
   *     the link lead to it; not taken for a recording with no file
   */
  public static List<Path> recordingFiles(Path first) {
    Objects.requireNonNull(first, "first must not be null: give the path the writer was opened with");
    // a writer opened at a symbolic link names its rotated files after the file the link leads to
    Path base;
    try {
      // a loop of links names no file: refused, rather than taken for no recording there
      base = SymbolicLinks.target(first, "list the files of the recording at",
          "give the path of the recording's first file, or make the link lead to it");
    } catch (IOException e) {
      throw new UncheckedIOException(e.getMessage(), e);
    }
    List<Path> files = new ArrayList<>();
    int index = 0;
    while (Files.exists(index == 0 ? first : McapWriter.rotatedPath(base, index))) {
      files.add(index == 0 ? first : McapWriter.rotatedPath(base, index));
      index++;
    }
    // a gap ends the recording; but a file of it just after the gap (one of the next
    // McapWriter.GAP_BRIDGED) says a file of it was moved or deleted, which reading on would hide
    SortedMap<Integer, Path> rotated = McapWriter.rotatedFilesIn(base);
    int later = rotated.isEmpty() ? -1 : rotated.lastKey();
    if (later > index) {
      throw new IllegalStateException(
          "file " + (index == 0 ? first : McapWriter.rotatedPath(base, index)) + " of the recording is missing, yet "
              + McapWriter.rotatedPath(base, later) + " exists: a file of the recording was"
              + " moved or deleted; put it back, or open the files there are one by one with"
              + " McapReader.open");
    }
    return files;
  }

  private McapFormatException problem(long offset, String message) {
    return new McapFormatException(path, offset, message);
  }

  private byte[] read(long offset, long length, String what) throws IOException {
    if (offset < 0 || length < 0 || offset + length > size) {
      throw problem(offset, what + " of " + length + " bytes runs past the end of the file ("
          + size + " bytes): the file is truncated or an offset in it is wrong");
    }
    if (length > Integer.MAX_VALUE - 8) {
      throw problem(offset, what + " is " + length + " bytes: too large to read");
    }
    ByteBuffer buffer = ByteBuffer.allocate((int) length);
    while (buffer.hasRemaining()) {
      if (file.read(buffer, offset + buffer.position()) < 0) {
        throw problem(offset + buffer.position(), "unexpected end of file reading " + what);
      }
    }
    return buffer.array();
  }

  private RecordCursor cursor(byte[] bytes, long fileOffset, String what) {
    return new RecordCursor(bytes, 0, bytes.length, fileOffset, what, this::problem);
  }

  private void readStructure() throws IOException {
    checkLeadingMagic();
    long headerEnd = readHeader();
    long minimum = headerEnd + FOOTER_LENGTH + Opcode.MAGIC.length;
    byte[] end = size >= minimum ? read(size - 8, 8, "the closing magic") : new byte[0];
    if (!Arrays.equals(end, Opcode.MAGIC)) {
      throw problem(Math.max(0, size - 8), "truncated or unfinished: the file does not end with the"
          + " MCAP magic, so it has no footer (the writer was not closed: crashed or still writing);"
          + " McapReader.openUnfinished reads the complete records it has, and McapMerge --unfinished"
          + " (Options.readUnfinished()) writes them to a finished file that a replay opens");
    }
    readFooterAndSummary(headerEnd);
  }

  private void checkLeadingMagic() throws IOException {
    byte[] start = read(0, Math.min(size, Opcode.MAGIC.length), "the leading magic");
    if (!Arrays.equals(start, Opcode.MAGIC)) {
      if (size == 0) {
        throw problem(0, "the file is empty (0 bytes): not an MCAP file");
      }
      if (start.length < 8 && Arrays.equals(start, Arrays.copyOf(Opcode.MAGIC, start.length))) {
        throw problem(0, "truncated: only " + size + " bytes, a part of the MCAP magic");
      }
      if (start.length == 8 && Arrays.equals(Arrays.copyOf(start, 5), Arrays.copyOf(Opcode.MAGIC, 5))) {
        throw problem(5, String.format(
            "MCAP major version byte 0x%02X is not supported (only 0x30, version 0)", start[5]));
      }
      throw problem(0, "not an MCAP file: it starts with " + hex(start)
          + " instead of the magic 89 4D 43 41 50 30 0D 0A");
    }
  }

  private void readFooterAndSummary(long headerEnd) throws IOException {
    long footerOffset = size - 8 - FOOTER_LENGTH;
    RecordCursor footer = cursor(read(footerOffset, FOOTER_LENGTH, "the Footer record"), footerOffset, "Footer record");
    int opcode = footer.u8("opcode");
    long length = footer.u64("length");
    if (opcode != Opcode.FOOTER || length != 20) {
      throw problem(footerOffset, "expected the Footer record before the closing magic, found "
          + Opcode.name(opcode) + " of length " + length);
    }
    summaryStart = footer.u64("summary_start");
    long summaryOffsetStart = footer.u64("summary_offset_start");
    long summaryCrc = footer.u32("summary_crc");
    if (summaryStart == 0) {
      scanDataSection(headerEnd, false);
      return;
    }
    if (summaryStart < headerEnd || summaryStart > footerOffset
        || (summaryOffsetStart != 0 && (summaryOffsetStart < summaryStart || summaryOffsetStart > footerOffset))) {
      throw problem(footerOffset, "the Footer's summary_start " + summaryStart + " or summary_offset_start "
          + summaryOffsetStart + " lies outside the file's summary area");
    }
    long summaryEnd = summaryOffsetStart != 0 ? summaryOffsetStart : footerOffset;
    checkSummaryStart(headerEnd, summaryEnd);
    byte[] summary = read(summaryStart, footerOffset - summaryStart, "the summary section");
    if (summaryCrc != 0) {
      CRC32 crc = new CRC32();
      crc.update(summary);
      crc.update(read(footerOffset, RECORD_PREFIX + 16, "the Footer record"));
      if (crc.getValue() != summaryCrc) {
        throw problem(summaryStart, String.format(
            "bad CRC: the summary section's CRC32 is %08X but the Footer says %08X: the summary is corrupt",
            crc.getValue(), summaryCrc));
      }
    }
    readSummary(summary, (int) (summaryEnd - summaryStart));
    if (statistics == null) {
      scanDataSection(headerEnd, false);
    }
  }

  /**
   * Checks that the Footer's summary_start points at a summary before the summary is read whole:
   * a corrupt one inside a large file would otherwise have up to 2 GiB read (and allocated) only
   * for the summary's CRC to tell. Cheap: the summary starts right after the DataEnd record that
   * ends the data section, as writers put it (its opcode and length are read). Where no DataEnd of
   * that length is there (a record between the two, a DataEnd of a later version with more
   * fields), the records from summary_start on are checked by their opcode and length only: each
   * must be one a summary may hold (no Chunk, Message, MessageIndex, Attachment, Metadata, Header,
   * Footer or DataEnd) and they must end where the summary ends.
   */
  private void checkSummaryStart(long headerEnd, long summaryEnd) throws IOException {
    long dataEnd = summaryStart - DATA_END_LENGTH;
    if (dataEnd >= headerEnd) {
      RecordCursor prefix = cursor(read(dataEnd, RECORD_PREFIX, "the DataEnd record"), dataEnd, "DataEnd record");
      if (prefix.u8("opcode") == Opcode.DATA_END && prefix.u64("length") == DATA_END_LENGTH - RECORD_PREFIX) {
        return;
      }
    }
    long offset = summaryStart;
    while (offset < summaryEnd) {
      RecordCursor prefix = cursor(read(offset, RECORD_PREFIX, "a summary record's opcode and length"), offset, "record");
      int opcode = prefix.u8("opcode");
      long length = prefix.u64("length");
      String noSummary = "the Footer's summary_start " + summaryStart + " points at no summary section (no DataEnd"
          + " record ends right before it): ";
      if (!mayBeInSummary(opcode)) {
        throw problem(offset, noSummary + "at byte " + offset + " is a " + Opcode.name(opcode)
            + " record, which a summary does not hold: summary_start is corrupt");
      }
      if (!fits(offset, length, summaryEnd)) {
        throw problem(offset, noSummary + "the " + Opcode.name(opcode) + " record at byte " + offset
            + " declares a length of " + Long.toUnsignedString(length) + " bytes, past the summary's end at byte "
            + summaryEnd + ": summary_start is corrupt");
      }
      offset += RECORD_PREFIX + length;
    }
  }

  /** Whether a record of this opcode may be in a summary section: any but the data section's own. */
  private static boolean mayBeInSummary(int opcode) {
    switch (opcode) {
      case Opcode.HEADER:
      case Opcode.FOOTER:
      case Opcode.MESSAGE:
      case Opcode.CHUNK:
      case Opcode.MESSAGE_INDEX:
      case Opcode.ATTACHMENT:
      case Opcode.METADATA:
      case Opcode.DATA_END:
        return false;
      default:
        return true;
    }
  }

  private long readHeader() throws IOException {
    long available = size - Opcode.MAGIC.length;
    if (available < RECORD_PREFIX) {
      throw problem(8, "truncated: the file ends before its Header record");
    }
    RecordCursor prefix = cursor(read(8, RECORD_PREFIX, "the Header record"), 8, "Header record");
    int opcode = prefix.u8("opcode");
    long length = prefix.u64("length");
    if (opcode != Opcode.HEADER) {
      throw problem(8, "the first record must be the Header, found " + Opcode.name(opcode));
    }
    RecordCursor header = cursor(read(8 + RECORD_PREFIX, length, "the Header record"), 8 + RECORD_PREFIX, "Header record");
    profile = header.string("profile");
    library = header.string("library");
    return 8 + RECORD_PREFIX + length;
  }

  private void readSummary(byte[] summary, int length) {
    RecordCursor records = new RecordCursor(summary, 0, length, summaryStart, "summary section", this::problem);
    while (records.remaining() > 0) {
      long recordOffset = records.fileOffset();
      int opcode = records.u8("opcode");
      long recordLength = records.u64(Opcode.name(opcode) + " length");
      byte[] content = records.bytes(recordLength, Opcode.name(opcode) + " content");
      RecordCursor record = cursor(content, recordOffset + RECORD_PREFIX, Opcode.name(opcode) + " record");
      switch (opcode) {
        case Opcode.SCHEMA:
          readSchema(record);
          break;
        case Opcode.CHANNEL:
          readChannel(record);
          break;
        case Opcode.STATISTICS:
          statistics = readStatistics(record);
          break;
        case Opcode.CHUNK_INDEX:
          readChunkIndex(record);
          break;
        case Opcode.METADATA_INDEX:
          long offset = record.u64("offset");
          long metadataLength = record.u64("length");
          metadataRecords.add(new long[] {offset, metadataLength});
          break;
        default:
          // other summary records (attachment indexes, private records) are not needed here
          break;
      }
    }
    summarised = true;
  }

  private void readSchema(RecordCursor record) {
    int id = record.u16("id");
    String name = record.string("name");
    String encoding = record.string("encoding");
    byte[] data = record.bytes32("data");
    if (id != 0) {
      schemas.put(id, new SchemaInfo(id, name, encoding, data));
    }
  }

  private void readChannel(RecordCursor record) {
    long at = record.fileOffset();
    int id = record.u16("id");
    int schemaId = record.u16("schema_id");
    String topic = record.string("topic");
    String encoding = record.string("message_encoding");
    Map<String, String> metadata = record.stringMap("metadata");
    SchemaInfo schema = null;
    if (schemaId != 0) {
      schema = schemas.get(schemaId);
      if (schema == null) {
        throw problem(at, "Channel " + id + " ('" + topic + "') refers to schema " + schemaId
            + " but no Schema record with that id comes before it");
      }
    }
    channels.putIfAbsent(id, new ChannelInfo(id, topic, encoding, Optional.ofNullable(schema),
        Collections.unmodifiableMap(metadata)));
  }

  private static McapStatistics readStatistics(RecordCursor record) {
    long messageCount = record.u64("message_count");
    int schemaCount = record.u16("schema_count");
    long channelCount = record.u32("channel_count");
    long attachmentCount = record.u32("attachment_count");
    long metadataCount = record.u32("metadata_count");
    long chunkCount = record.u32("chunk_count");
    long startTime = record.u64("message_start_time");
    long endTime = record.u64("message_end_time");
    Map<Integer, Long> counts = new TreeMap<>(record.u16u64Map("channel_message_counts"));
    return new McapStatistics(messageCount, schemaCount, channelCount, attachmentCount, metadataCount,
        chunkCount, startTime, endTime, Collections.unmodifiableMap(counts));
  }

  private void readChunkIndex(RecordCursor record) {
    long startTime = record.u64("message_start_time");
    record.u64("message_end_time");
    long offset = record.u64("chunk_start_offset");
    long length = record.u64("chunk_length");
    Map<Integer, Long> indexOffsets = record.u16u64Map("message_index_offsets");
    // An empty map means "no message index": the chunk may hold any channel.
    chunks.add(new ChunkRef(startTime, offset, length,
        indexOffsets.isEmpty() ? null : Set.copyOf(indexOffsets.keySet()), false));
  }

  /** One pass over the data section, for files without a summary (or without statistics). */
  private void scanDataSection(long from, boolean unfinished) throws IOException {
    if (summarised) {
      chunks.clear();
      metadataRecords.clear();
    }
    long messageCount = 0;
    long chunkCount = 0;
    long first = Long.MAX_VALUE;
    long last = Long.MIN_VALUE;
    Map<Integer, Long> counts = new TreeMap<>();
    long limit = unfinished ? size : size - 8 - FOOTER_LENGTH;
    long offset = from;
    boolean cut = false;
    Salvage salvaged = null;
    long dataEnd = -1;
    while (offset < limit) {
      if (unfinished && offset + RECORD_PREFIX > size) {
        cut = true;
        break;
      }
      RecordCursor prefix = cursor(read(offset, RECORD_PREFIX, "a record's opcode and length"), offset, "record");
      int opcode = prefix.u8("opcode");
      long length = prefix.u64("length");
      if (opcode == Opcode.DATA_END) {
        dataEnd = offset;
        break;
      }
      boolean fits = fits(offset, length, limit);
      if (unfinished && (opcode == 0 || !fits)) {
        // the record the writer was writing when it stopped (or zeroes after it)
        cut = true;
        if (opcode == Opcode.CHUNK) {
          salvaged = salvageChunk(offset, length, false);
        }
        break;
      }
      if (!fits) {
        throw tooLong(offset, opcode, length, limit);
      }
      long total = RECORD_PREFIX + length;
      // a Chunk's records may define schemas and channels before one of them proves damaged
      Map<Integer, SchemaInfo> schemasBefore = unfinished && opcode == Opcode.CHUNK ? new TreeMap<>(schemas) : null;
      Map<Integer, ChannelInfo> channelsBefore = unfinished && opcode == Opcode.CHUNK ? new TreeMap<>(channels) : null;
      try {
        if (opcode == Opcode.CHUNK) {
          List<McapMessage> messages = loadChunk(new ChunkRef(0, offset, total, null, false), id -> true);
          Set<Integer> ids = messages.stream().map(m -> m.channel().id()).collect(Collectors.toSet());
          long startTime = messages.isEmpty() ? 0 : messages.get(0).logTime();
          chunks.add(new ChunkRef(startTime, offset, total, ids, false));
          chunkCount++;
          for (McapMessage m : messages) {
            messageCount++;
            counts.merge(m.channel().id(), 1L, Long::sum);
            first = Math.min(first, m.logTime());
            last = Math.max(last, m.logTime());
          }
        } else if (opcode == Opcode.MESSAGE || opcode == Opcode.SCHEMA || opcode == Opcode.CHANNEL) {
          byte[] content = read(offset + RECORD_PREFIX, length, Opcode.name(opcode) + " record");
          RecordCursor record = cursor(content, offset + RECORD_PREFIX, Opcode.name(opcode) + " record");
          if (opcode == Opcode.SCHEMA) {
            readSchema(record);
          } else if (opcode == Opcode.CHANNEL) {
            readChannel(record);
          } else {
            McapMessage m = readMessage(record, content.length, id -> true);
            chunks.add(new ChunkRef(m.logTime(), offset, total, Set.of(m.channel().id()), true));
            messageCount++;
            counts.merge(m.channel().id(), 1L, Long::sum);
            first = Math.min(first, m.logTime());
            last = Math.max(last, m.logTime());
          }
        } else if (opcode == Opcode.METADATA) {
          metadataRecords.add(new long[] {offset, total});
        }
      } catch (McapFormatException damaged) {
        if (!unfinished) {
          throw damaged;
        }
        // a record whose bytes never reached the disk (a power cut leaves zeroes where the file
        // was extended for it) or are damaged: the complete records end before it
        if (schemasBefore != null) {
          schemas.clear();
          schemas.putAll(schemasBefore);
          channels.clear();
          channels.putAll(channelsBefore);
          salvaged = salvageChunk(offset, length, true);
        }
        cut = true;
        break;
      }
      offset += total;
    }
    if (offset >= limit && !unfinished) {
      throw problem(offset, "the data section has no DataEnd record before the Footer");
    }
    if (salvaged != null) {
      chunks.addAll(salvaged.refs());
      for (McapMessage m : salvaged.messages()) {
        messageCount++;
        counts.merge(m.channel().id(), 1L, Long::sum);
        first = Math.min(first, m.logTime());
        last = Math.max(last, m.logTime());
      }
      offset = salvaged.end();
    }
    if (unfinished && dataEnd >= 0 && !endsWithFooter()) {
      // the writer stopped while writing the summary: every record of the data section is there
      recoveredUpTo = dataEnd + DATA_END_LENGTH <= size ? dataEnd + DATA_END_LENGTH : dataEnd;
    } else {
      recoveredUpTo = cut || offset >= limit ? offset : -1;
    }
    statistics = new McapStatistics(messageCount, schemas.size(), channels.size(), 0, metadataRecords.size(),
        chunkCount, messageCount == 0 ? 0 : first, messageCount == 0 ? 0 : last,
        Collections.unmodifiableMap(counts));
  }

  /**
   * What a Chunk cut short or damaged still holds whole: its Message records, each read as a lone
   * message ({@code refs}, {@code messages}), and where its last whole record ends ({@code end}).
   */
  private record Salvage(List<ChunkRef> refs, List<McapMessage> messages, long end) {}

  /**
   * The whole records at the start of a Chunk that the writer was writing when it stopped: cut
   * short by the end of the file, or ending in zeroes (bytes that never reached the disk, which a
   * power cut leaves where the file was extended), which is why its CRC does not check. The bytes
   * before the cut or the zeroes are as written, so the records that end before it are read (the
   * Schema and Channel records defined, the Messages kept); a record that reaches into it is not.
   * A damaged Chunk that does not end in zeroes (corrupt, not unwritten) gives nothing, nor does a
   * compressed one or one whose header is cut.
   */
  private Salvage salvageChunk(long offset, long length, boolean damaged) throws IOException {
    Salvage nothing = new Salvage(List.of(), List.of(), offset);
    long end = fits(offset, length, size) ? offset + RECORD_PREFIX + length : size;
    if (end - offset > Integer.MAX_VALUE - 8) {
      return nothing;
    }
    byte[] bytes = read(offset, end - offset, "a Chunk record");
    int trusted = bytes.length;
    while (trusted > 0 && bytes[trusted - 1] == 0) {
      trusted--;
    }
    if (damaged && trusted == bytes.length) {
      return nothing;
    }
    RecordCursor chunk = new RecordCursor(bytes, 0, trusted, offset, "Chunk record", this::problem);
    Map<Integer, SchemaInfo> schemasBefore = new TreeMap<>(schemas);
    Map<Integer, ChannelInfo> channelsBefore = new TreeMap<>(channels);
    List<ChunkRef> refs = new ArrayList<>();
    List<McapMessage> messages = new ArrayList<>();
    long wholeUpTo = offset;
    try {
      chunk.u8("opcode");
      chunk.u64("length");
      chunk.u64("message_start_time");
      chunk.u64("message_end_time");
      chunk.u64("uncompressed_size");
      chunk.u32("uncompressed_crc");
      if (!chunk.string("compression").isEmpty()) {
        return nothing;
      }
      chunk.u64("records length");
      while (chunk.remaining() >= RECORD_PREFIX) {
        long recordOffset = chunk.fileOffset();
        int inner = chunk.u8("opcode");
        long innerLength = chunk.u64(Opcode.name(inner) + " length");
        if (inner == 0 || innerLength < 0 || innerLength > chunk.remaining()) {
          break; // reaches into the cut or the zeroes
        }
        byte[] content = chunk.bytes(innerLength, Opcode.name(inner) + " content");
        McapMessage m = readChunkRecord(inner, content, recordOffset, id -> true);
        if (m != null) {
          refs.add(new ChunkRef(m.logTime(), recordOffset, RECORD_PREFIX + innerLength, Set.of(m.channel().id()), true));
          messages.add(m);
        }
        wholeUpTo = chunk.fileOffset();
      }
    } catch (McapFormatException e) {
      // a record that does not parse ends what is taken, as the cut does
    }
    if (wholeUpTo == offset) {
      schemas.clear();
      schemas.putAll(schemasBefore);
      channels.clear();
      channels.putAll(channelsBefore);
    }
    return new Salvage(refs, messages, wholeUpTo);
  }

  /** Whether the file ends with a Footer record and the closing magic, as a finished file does. */
  private boolean endsWithFooter() throws IOException {
    long footerOffset = size - Opcode.MAGIC.length - FOOTER_LENGTH;
    return footerOffset > 0
        && Arrays.equals(read(size - Opcode.MAGIC.length, Opcode.MAGIC.length, "the closing magic"), Opcode.MAGIC)
        && read(footerOffset, 1, "the Footer record")[0] == Opcode.FOOTER;
  }

  /**
   * Reads one record of a chunk's records, found at {@code recordOffset} with {@code content}: a
   * Schema or a Channel is taken in; a Message is returned if its channel is {@code wanted}.
   *
   * @return the message, or null for any other record or a message not wanted
   */
  private McapMessage readChunkRecord(int opcode, byte[] content, long recordOffset, IntPredicate wanted) {
    RecordCursor record = cursor(content, recordOffset + RECORD_PREFIX, Opcode.name(opcode) + " record");
    if (opcode == Opcode.SCHEMA) {
      readSchema(record);
    } else if (opcode == Opcode.CHANNEL) {
      readChannel(record);
    } else if (opcode == Opcode.MESSAGE) {
      return readMessage(record, content.length, wanted);
    }
    return null;
  }

  private McapMessage readMessage(RecordCursor record, int length, IntPredicate wanted) {
    long at = record.fileOffset();
    int start = record.position();
    int channelId = record.u16("channel_id");
    long sequence = record.u32("sequence");
    long logTime = record.u64("log_time");
    long publishTime = record.u64("publish_time");
    if (!wanted.test(channelId)) {
      record.bytes(length - (record.position() - start), "data");
      return null;
    }
    ChannelInfo channel = channels.get(channelId);
    if (channel == null) {
      throw problem(at, "a Message refers to channel " + channelId + " but no Channel record defines it");
    }
    byte[] data = record.bytes(length - (record.position() - start), "data");
    return new McapMessage(channel, sequence, logTime, publishTime, data);
  }

  /** The messages of one chunk (or lone message) on the wanted channels, in log-time order. */
  private List<McapMessage> loadChunk(ChunkRef ref, IntPredicate wanted) throws IOException {
    byte[] bytes = read(ref.offset(), ref.length(), ref.loneMessage() ? "a Message record" : "a Chunk record");
    RecordCursor chunk = cursor(bytes, ref.offset(), ref.loneMessage() ? "Message record" : "Chunk record");
    int opcode = chunk.u8("opcode");
    long length = chunk.u64("length");
    if (ref.loneMessage()) {
      McapMessage m = readMessage(chunk, (int) length, wanted);
      return m == null ? List.of() : List.of(m);
    }
    if (opcode != Opcode.CHUNK) {
      throw problem(ref.offset(), "a ChunkIndex points here but the record is " + Opcode.name(opcode)
          + ", not a Chunk: the summary does not match the data");
    }
    if (length != ref.length() - RECORD_PREFIX) {
      throw problem(ref.offset(), "the Chunk's length " + length + " differs from its ChunkIndex's "
          + (ref.length() - RECORD_PREFIX));
    }
    chunk.u64("message_start_time");
    chunk.u64("message_end_time");
    long uncompressedSize = chunk.u64("uncompressed_size");
    long crc = chunk.u32("uncompressed_crc");
    String compression = chunk.string("compression");
    long recordsLength = chunk.u64("records length");
    if (!compression.isEmpty()) {
      throw problem(ref.offset(), "the chunk is compressed with '" + compression + "': this reader reads"
          + " uncompressed chunks only (prime-mcap writes them); decompress the file first"
          + " (`mcap decompress` of the mcap command-line tool)");
    }
    if (recordsLength != uncompressedSize || recordsLength != chunk.remaining()) {
      throw problem(ref.offset(), "the Chunk says its records are " + recordsLength + " bytes (uncompressed_size "
          + uncompressedSize + ") but " + chunk.remaining() + " bytes are left in the record");
    }
    int recordsStart = chunk.position();
    long recordsOffset = chunk.fileOffset();
    if (crc != 0) {
      CRC32 actual = new CRC32();
      actual.update(bytes, recordsStart, (int) recordsLength);
      if (actual.getValue() != crc) {
        throw problem(ref.offset(), String.format(
            "bad CRC: the chunk's records have CRC32 %08X but the Chunk says %08X: the chunk is corrupt",
            actual.getValue(), crc));
      }
    }
    RecordCursor records = new RecordCursor(bytes, recordsStart, (int) recordsLength,
        recordsOffset, "records of the Chunk at byte " + ref.offset(), this::problem);
    List<McapMessage> messages = new ArrayList<>();
    while (records.remaining() > 0) {
      long recordOffset = records.fileOffset();
      int inner = records.u8("opcode");
      long innerLength = records.u64(Opcode.name(inner) + " length");
      byte[] content = records.bytes(innerLength, Opcode.name(inner) + " content");
      McapMessage m = readChunkRecord(inner, content, recordOffset, wanted);
      if (m != null) {
        messages.add(m);
      }
    }
    messages.sort(Comparator.comparingLong(McapMessage::logTime));
    return messages;
  }

  /** @return the file */
  public Path path() {
    return path;
  }

  /** @return the Header's profile ("" for prime-mcap files) */
  public String profile() {
    return profile;
  }

  /** @return the Header's library (the writer's name) */
  public String library() {
    return library;
  }

  /** @return the channels, by id */
  public List<ChannelInfo> channels() {
    return List.copyOf(channels.values());
  }

  /**
   * @param topic a topic
   * @return its channel (the first with that topic)
   */
  public Optional<ChannelInfo> channel(String topic) {
    return channels.values().stream().filter(c -> c.topic().equals(topic)).findFirst();
  }

  /** @return the schemas, by id */
  public List<SchemaInfo> schemas() {
    return List.copyOf(schemas.values());
  }

  /** @return the statistics (from the summary; counted in one pass if the file has none) */
  public McapStatistics statistics() {
    return statistics;
  }

  /**
   * @return for a reader from {@link #openUnfinished} of a file that was not finished, the
   *     offset where its last complete record ends (what follows was cut off); -1 otherwise
   */
  public long unfinishedAt() {
    return recoveredUpTo;
  }

  /** @return whether the channels and statistics came from a summary section, without a data scan */
  public boolean hasSummary() {
    return summarised && summaryStart != 0;
  }

  /**
   * @param topic a topic
   * @return its message count, from the statistics
   * @throws IllegalArgumentException if no channel has the topic
   */
  public long messageCount(String topic) {
    ChannelInfo channel = requireChannel(topic);
    return statistics.channelMessageCounts().getOrDefault(channel.id(), 0L);
  }

  private ChannelInfo requireChannel(String topic) {
    return channel(topic).orElseThrow(() -> new IllegalArgumentException(
        "no channel has topic '" + topic + "' in " + path + "; its topics are "
            + channels.values().stream().map(ChannelInfo::topic).collect(Collectors.toList())));
  }

  /**
   * @param name a Metadata record name (for instance {@link McapWriter#LOSS_METADATA})
   * @return the key/value pairs of every Metadata record with that name, in file order
   * @throws IOException if reading fails
   */
  public List<Map<String, String>> metadata(String name) throws IOException {
    List<Map<String, String>> found = new ArrayList<>();
    for (long[] ref : metadataRecords) {
      RecordCursor record = metadataRecord(ref);
      if (record.string("name").equals(name)) {
        found.add(Collections.unmodifiableMap(record.stringMap("metadata")));
      }
    }
    return found;
  }

  /**
   * @return the names of the file's Metadata records, each once, in the order they first appear
   *     (read each with {@link #metadata(String)})
   * @throws IOException if reading fails
   */
  public List<String> metadataNames() throws IOException {
    Set<String> names = new LinkedHashSet<>();
    for (long[] ref : metadataRecords) {
      names.add(metadataRecord(ref).string("name"));
    }
    return List.copyOf(names);
  }

  /** The Metadata record at {@code ref} (offset, length), positioned at its name. */
  private RecordCursor metadataRecord(long[] ref) throws IOException {
    byte[] bytes = read(ref[0], ref[1], "a Metadata record");
    RecordCursor record = cursor(bytes, ref[0], "Metadata record");
    int opcode = record.u8("opcode");
    record.u64("length");
    if (opcode != Opcode.METADATA) {
      throw problem(ref[0], "a MetadataIndex points here but the record is " + Opcode.name(opcode));
    }
    return record;
  }

  /**
   * Every message of the file, in log-time order (equal times in file order). Lazy: chunks are
   * read as the stream reaches them; the reader must stay open while the stream is used.
   *
   * @return the messages
   */
  public Stream<McapMessage> messages() {
    return stream(null);
  }

  /**
   * The messages of one topic, undecoded, in log-time order.
   *
   * @param topic the topic
   * @return its messages
   * @throws IllegalArgumentException if no channel has the topic
   */
  public Stream<McapMessage> messages(String topic) {
    return stream(requireChannel(topic).id());
  }

  /**
   * The messages of one topic decoded into a type of the caller's choice, in log-time order.
   *
   * @param topic the topic
   * @param type the values' class
   * @param <T> the values' type
   * @return the decoded messages
   * @throws IllegalArgumentException if no channel has the topic; from the stream, if a message
   *     is not a {@code T}
   */
  public <T> Stream<TypedMessage<T>> messages(String topic, Class<T> type) {
    return messages(topic, ValueType.of(type));
  }

  /**
   * The messages of one topic decoded into a (generic) type of the caller's choice.
   *
   * @param topic the topic
   * @param type the values' type
   * @param <T> the values' type
   * @return the decoded messages
   * @throws IllegalArgumentException if no channel has the topic; from the stream, if a message
   *     is not a {@code T}
   */
  public <T> Stream<TypedMessage<T>> messages(String topic, ValueType<T> type) {
    Objects.requireNonNull(type, "type must not be null: give the values' type to decode them into");
    return messages(topic).map(m -> new TypedMessage<>(topic, m.sequence(), m.logTime(), m.publishTime(), m.decode(type)));
  }

  private Stream<McapMessage> stream(Integer channelId) {
    IntPredicate wanted = channelId == null ? id -> true : id -> id == channelId;
    Iterator<McapMessage> merge = new LogTimeMerge(chunks, channelId, ref -> {
      try {
        return loadChunk(ref, wanted);
      } catch (IOException e) {
        throw new UncheckedIOException("reading " + path + " at byte " + ref.offset(), e);
      }
    });
    return StreamSupport.stream(Spliterators.spliteratorUnknownSize(merge, Spliterator.ORDERED | Spliterator.NONNULL), false);
  }

  /**
   * Checks the whole file: the data section's CRC32 against the DataEnd record and every
   * chunk's CRC32.
   *
   * @throws McapFormatException naming the first mismatch
   * @throws IOException if reading fails
   */
  public void verify() throws IOException {
    long dataEnd = findDataEnd();
    RecordCursor record = cursor(read(dataEnd, DATA_END_LENGTH, "the DataEnd record"), dataEnd, "DataEnd record");
    record.u8("opcode");
    record.u64("length");
    long expected = record.u32("data_section_crc");
    if (expected != 0) {
      CRC32 crc = new CRC32();
      ByteBuffer buffer = ByteBuffer.allocate(1 << 16);
      long position = 0;
      while (position < dataEnd) {
        buffer.clear();
        buffer.limit((int) Math.min(buffer.capacity(), dataEnd - position));
        int n = file.read(buffer, position);
        if (n < 0) {
          throw problem(position, "unexpected end of file");
        }
        buffer.flip();
        crc.update(buffer);
        position += n;
      }
      if (crc.getValue() != expected) {
        throw problem(0, String.format(
            "bad CRC: the data section's CRC32 is %08X but the DataEnd record says %08X: the data is corrupt",
            crc.getValue(), expected));
      }
    }
    for (ChunkRef ref : chunks) {
      loadChunk(ref, id -> true);
    }
  }

  private long findDataEnd() throws IOException {
    if (summaryStart != 0) {
      long candidate = summaryStart - DATA_END_LENGTH;
      if (candidate > 0 && read(candidate, 1, "the DataEnd record")[0] == Opcode.DATA_END) {
        return candidate;
      }
    }
    long offset = 8;
    long limit = size - 8 - FOOTER_LENGTH;
    while (offset < limit) {
      RecordCursor prefix = cursor(read(offset, RECORD_PREFIX, "a record's opcode and length"), offset, "record");
      int opcode = prefix.u8("opcode");
      long length = prefix.u64("length");
      if (opcode == Opcode.DATA_END) {
        return offset;
      }
      if (!fits(offset, length, limit)) {
        throw tooLong(offset, opcode, length, limit);
      }
      offset += RECORD_PREFIX + length;
    }
    throw problem(offset, "the data section has no DataEnd record before the Footer");
  }

  /**
   * Whether a record at {@code offset} whose prefix declares {@code length} (a uint64: 2^63 and
   * more read as negative) ends by {@code limit}; computed without overflow, so that a corrupt
   * length can neither move a pass over the records backwards nor leave it in place.
   */
  private static boolean fits(long offset, long length, long limit) {
    return length >= 0 && length <= limit - offset - RECORD_PREFIX;
  }

  private McapFormatException tooLong(long offset, int opcode, long length, long limit) {
    return problem(offset, Opcode.name(opcode) + " record declares a length of "
        + Long.toUnsignedString(length) + " bytes, which runs past the end of the data section at byte "
        + limit + ": its length is corrupt");
  }

  @Override
  public void close() throws IOException {
    file.close();
  }

  private static String hex(byte[] bytes) {
    StringBuilder s = new StringBuilder();
    for (byte b : bytes) {
      if (s.length() > 0) {
        s.append(' ');
      }
      s.append(String.format("%02X", b & 0xFF));
    }
    return s.toString();
  }
}
