package dev.prime.mcap;

import java.util.Map;

/**
 * The Statistics record of an MCAP file's summary: counts without reading the data section.
 *
 * @param messageCount messages in the file
 * @param schemaCount schemas
 * @param channelCount channels
 * @param attachmentCount attachments
 * @param metadataCount metadata records
 * @param chunkCount chunks
 * @param messageStartTime earliest log time, 0 with no messages
 * @param messageEndTime latest log time, 0 with no messages
 * @param channelMessageCounts messages per channel id
 */
public record McapStatistics(
    long messageCount,
    int schemaCount,
    long channelCount,
    long attachmentCount,
    long metadataCount,
    long chunkCount,
    long messageStartTime,
    long messageEndTime,
    Map<Integer, Long> channelMessageCounts) {}
