package dev.prime.mcap.internal;

import java.io.IOException;
import java.nio.ByteBuffer;
import java.nio.channels.FileChannel;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import java.util.zip.CRC32;

/**
 * Writes one MCAP file, start to end, from one thread: magic and Header; Schema, Channel and
 * Message records batched into uncompressed Chunks, each followed by a MessageIndex per channel;
 * Metadata records; DataEnd with the CRC32 of the data section; a summary section (Schemas,
 * Channels, Statistics, ChunkIndexes, MetadataIndexes, grouped by opcode), SummaryOffsets, the
 * Footer with the summary's CRC32, and the closing magic.
 *
 * <p>Memory: the open chunk (about the chunk size), plus per chunk written one ChunkIndex (about
 * 70 bytes and 10 per channel in it), plus the schemas and channels.
 *
 * <p>Durability: records are handed to the operating system as chunks close, never forced (a
 * message is a hot path); {@link #finish()} forces the finished file to the storage device before
 * it returns, when made to.
 */
public final class McapFileWriter {
  private final FileChannel out;
  private final boolean force;
  private final long chunkSize;
  private final CRC32 dataCrc = new CRC32();
  private long position;

  private final RecordBuffer scratch = new RecordBuffer(256);
  private final RecordBuffer chunk;
  private long chunkStart = Long.MAX_VALUE;
  private long chunkEnd = Long.MIN_VALUE;
  private boolean chunkHasMessages;
  private boolean chunkHasRecords;
  /** channel id -> (log time, offset in chunk) pairs, flattened. */
  private final Map<Integer, List<long[]>> chunkMessageIndex = new TreeMap<>();

  private final Map<Integer, byte[]> schemaRecords = new LinkedHashMap<>();
  private final Map<Integer, byte[]> channelRecords = new LinkedHashMap<>();
  private final Map<Integer, Long> channelMessageCounts = new TreeMap<>();
  private final List<byte[]> chunkIndexRecords = new ArrayList<>();
  private final List<byte[]> metadataIndexRecords = new ArrayList<>();
  private long messageCount;
  private long firstLogTime = Long.MAX_VALUE;
  private long lastLogTime = Long.MIN_VALUE;
  private long chunkCount;
  private boolean finished;

  /**
   * Writes the magic and the Header.
   *
   * @param out where the file goes (this writer closes it in {@link #finish()})
   * @param library the Header's library string
   * @param chunkSize a chunk is closed once its records reach this many bytes
   * @param force whether {@link #finish()} forces the file to the storage device (a regular
   *     file); false for a device or a pipe, which cannot be forced
   * @throws IOException from {@code out}
   */
  public McapFileWriter(FileChannel out, String library, long chunkSize, boolean force) throws IOException {
    this.out = out;
    this.force = force;
    this.chunkSize = chunkSize;
    this.chunk = new RecordBuffer((int) Math.min(chunkSize + 1024, 1 << 20));
    emit(Opcode.MAGIC, 0, Opcode.MAGIC.length);
    scratch.clear();
    int at = scratch.beginRecord(Opcode.HEADER);
    scratch.string("");
    scratch.string(library);
    scratch.endRecord(at);
    emit(scratch);
  }

  /** @return bytes written to the file so far plus those of the open chunk */
  public long size() {
    return position + chunk.size();
  }

  /**
   * @param schemaId a schema id
   * @return whether this file has the schema
   */
  public boolean hasSchema(int schemaId) {
    return schemaRecords.containsKey(schemaId);
  }

  /**
   * @param channelId a channel id
   * @return whether this file has the channel
   */
  public boolean hasChannel(int channelId) {
    return channelRecords.containsKey(channelId);
  }

  /**
   * Adds a Schema record to the open chunk and the summary.
   *
   * @param id schema id, 1..65535
   * @param name schema name
   * @param encoding schema encoding
   * @param data schema bytes
   */
  public void addSchema(int id, String name, String encoding, byte[] data) {
    RecordBuffer r = new RecordBuffer(64 + data.length);
    int at = r.beginRecord(Opcode.SCHEMA);
    r.u16(id);
    r.string(name);
    r.string(encoding);
    r.bytes32(data);
    r.endRecord(at);
    byte[] record = r.toByteArray();
    schemaRecords.put(id, record);
    chunk.raw(record, 0, record.length);
    chunkHasRecords = true;
  }

  /**
   * Adds a Channel record to the open chunk and the summary.
   *
   * @param id channel id
   * @param schemaId its schema (added before)
   * @param topic topic
   * @param messageEncoding message encoding
   * @param metadata channel metadata
   */
  public void addChannel(int id, int schemaId, String topic, String messageEncoding, Map<String, String> metadata) {
    RecordBuffer r = new RecordBuffer(64);
    int at = r.beginRecord(Opcode.CHANNEL);
    r.u16(id);
    r.u16(schemaId);
    r.string(topic);
    r.string(messageEncoding);
    r.stringMap(metadata);
    r.endRecord(at);
    byte[] record = r.toByteArray();
    channelRecords.put(id, record);
    channelMessageCounts.putIfAbsent(id, 0L);
    chunk.raw(record, 0, record.length);
    chunkHasRecords = true;
  }

  /**
   * Adds a Message record to the open chunk; closes the chunk once it reaches the chunk size.
   *
   * @param channelId its channel (added before)
   * @param sequence sequence number (its low 32 bits are kept)
   * @param logTime log time, nanoseconds
   * @param publishTime publish time, nanoseconds
   * @param data message bytes
   * @throws IOException from the output
   */
  public void addMessage(int channelId, long sequence, long logTime, long publishTime, byte[] data) throws IOException {
    long offset = chunk.size();
    int at = chunk.beginRecord(Opcode.MESSAGE);
    chunk.u16(channelId);
    chunk.u32(sequence);
    chunk.u64(logTime);
    chunk.u64(publishTime);
    chunk.raw(data, 0, data.length);
    chunk.endRecord(at);
    chunkMessageIndex.computeIfAbsent(channelId, id -> new ArrayList<>()).add(new long[] {logTime, offset});
    chunkHasRecords = true;
    chunkHasMessages = true;
    chunkStart = Math.min(chunkStart, logTime);
    chunkEnd = Math.max(chunkEnd, logTime);
    firstLogTime = Math.min(firstLogTime, logTime);
    lastLogTime = Math.max(lastLogTime, logTime);
    messageCount++;
    channelMessageCounts.merge(channelId, 1L, Long::sum);
    if (chunk.size() >= chunkSize) {
      flushChunk();
    }
  }

  /**
   * Writes a Metadata record in the data section (after closing the open chunk: metadata does
   * not go into chunks) and indexes it in the summary.
   *
   * @param name record name
   * @param metadata key/value pairs
   * @throws IOException from the output
   */
  public void addMetadata(String name, Map<String, String> metadata) throws IOException {
    flushChunk();
    long offset = position;
    scratch.clear();
    int at = scratch.beginRecord(Opcode.METADATA);
    scratch.string(name);
    scratch.stringMap(metadata);
    scratch.endRecord(at);
    long length = scratch.size();
    emit(scratch);
    RecordBuffer index = new RecordBuffer(32 + name.length());
    int indexAt = index.beginRecord(Opcode.METADATA_INDEX);
    index.u64(offset);
    index.u64(length);
    index.string(name);
    index.endRecord(indexAt);
    metadataIndexRecords.add(index.toByteArray());
  }

  /**
   * Writes the open chunk, if it has records, and its message indexes.
   *
   * @throws IOException from the output
   */
  public void flushChunk() throws IOException {
    if (!chunkHasRecords) {
      return;
    }
    long start = chunkHasMessages ? chunkStart : 0;
    long end = chunkHasMessages ? chunkEnd : 0;
    long chunkOffset = position;
    scratch.clear();
    int at = scratch.beginRecord(Opcode.CHUNK);
    scratch.u64(start);
    scratch.u64(end);
    scratch.u64(chunk.size());
    scratch.u32(chunk.crc32());
    scratch.string("");
    scratch.u64(chunk.size());
    // the records follow; the content length counts them
    scratch.patchU64(at, scratch.size() - at - 8L + chunk.size());
    emit(scratch);
    emit(chunk.array(), 0, chunk.size());
    long chunkLength = position - chunkOffset;

    Map<Integer, Long> indexOffsets = new TreeMap<>();
    long indexStart = position;
    scratch.clear();
    for (Map.Entry<Integer, List<long[]>> e : chunkMessageIndex.entrySet()) {
      List<long[]> entries = e.getValue();
      entries.sort((a, b) -> a[0] != b[0] ? Long.compare(a[0], b[0]) : Long.compare(a[1], b[1]));
      indexOffsets.put(e.getKey(), position + scratch.size());
      int indexAt = scratch.beginRecord(Opcode.MESSAGE_INDEX);
      scratch.u16(e.getKey());
      scratch.u32(entries.size() * 16L);
      for (long[] entry : entries) {
        scratch.u64(entry[0]);
        scratch.u64(entry[1]);
      }
      scratch.endRecord(indexAt);
    }
    emit(scratch);
    long indexLength = position - indexStart;

    RecordBuffer index = new RecordBuffer(96 + 10 * indexOffsets.size());
    int indexAt = index.beginRecord(Opcode.CHUNK_INDEX);
    index.u64(start);
    index.u64(end);
    index.u64(chunkOffset);
    index.u64(chunkLength);
    index.u16u64Map(indexOffsets);
    index.u64(indexLength);
    index.string("");
    index.u64(chunk.size());
    index.u64(chunk.size());
    index.endRecord(indexAt);
    chunkIndexRecords.add(index.toByteArray());
    chunkCount++;

    chunk.clear();
    chunkMessageIndex.clear();
    chunkHasRecords = false;
    chunkHasMessages = false;
    chunkStart = Long.MAX_VALUE;
    chunkEnd = Long.MIN_VALUE;
  }

  /**
   * Closes the open chunk, writes DataEnd, the summary, the summary offsets, the footer and the
   * closing magic, forces the file to the storage device (if made to: its bytes and its size, so
   * that a power cut after this returns leaves the file finished), and closes the output.
   *
   * @throws IOException from the output
   */
  public void finish() throws IOException {
    if (finished) {
      return;
    }
    finished = true;
    try {
      flushChunk();
      scratch.clear();
      int at = scratch.beginRecord(Opcode.DATA_END);
      scratch.u32(dataCrc.getValue());
      scratch.endRecord(at);
      emit(scratch);

      long summaryStart = position;
      RecordBuffer summary = new RecordBuffer(4096);
      List<long[]> groups = new ArrayList<>();
      group(summary, groups, Opcode.SCHEMA, schemaRecords.values());
      group(summary, groups, Opcode.CHANNEL, channelRecords.values());
      group(summary, groups, Opcode.STATISTICS, List.of(statistics()));
      group(summary, groups, Opcode.CHUNK_INDEX, chunkIndexRecords);
      group(summary, groups, Opcode.METADATA_INDEX, metadataIndexRecords);
      long summaryOffsetStart = summaryStart + summary.size();
      for (long[] g : groups) {
        int offsetAt = summary.beginRecord(Opcode.SUMMARY_OFFSET);
        summary.u8((int) g[0]);
        summary.u64(summaryStart + g[1]);
        summary.u64(g[2]);
        summary.endRecord(offsetAt);
      }
      // the footer's CRC covers the summary up to and including summary_offset_start
      summary.u8(Opcode.FOOTER);
      summary.u64(8 + 8 + 4);
      summary.u64(summaryStart);
      summary.u64(summaryOffsetStart);
      summary.u32(summary.crc32());
      emit(summary);
      emit(Opcode.MAGIC, 0, Opcode.MAGIC.length);
      if (force) {
        out.force(true);
      }
    } finally {
      out.close();
    }
  }

  /**
   * Closes the output without finishing the file (after a failure).
   *
   * @throws IOException from closing
   */
  public void abandon() throws IOException {
    finished = true;
    out.close();
  }

  private static void group(RecordBuffer summary, List<long[]> groups, int opcode, Iterable<byte[]> records) {
    long start = summary.size();
    for (byte[] record : records) {
      summary.raw(record, 0, record.length);
    }
    if (summary.size() > start) {
      groups.add(new long[] {opcode, start, summary.size() - start});
    }
  }

  private byte[] statistics() {
    RecordBuffer r = new RecordBuffer(64 + 10 * channelMessageCounts.size());
    int at = r.beginRecord(Opcode.STATISTICS);
    r.u64(messageCount);
    r.u16(schemaRecords.size());
    r.u32(channelRecords.size());
    r.u32(0);
    r.u32(metadataIndexRecords.size());
    r.u32(chunkCount);
    r.u64(messageCount == 0 ? 0 : firstLogTime);
    r.u64(messageCount == 0 ? 0 : lastLogTime);
    r.u16u64Map(channelMessageCounts);
    r.endRecord(at);
    return r.toByteArray();
  }

  private void emit(RecordBuffer buffer) throws IOException {
    emit(buffer.array(), 0, buffer.size());
  }

  private void emit(byte[] bytes, int offset, int length) throws IOException {
    ByteBuffer buffer = ByteBuffer.wrap(bytes, offset, length);
    while (buffer.hasRemaining()) {
      out.write(buffer);
    }
    dataCrc.update(bytes, offset, length);
    position += length;
  }
}
