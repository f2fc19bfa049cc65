package dev.prime.mcap;

import java.util.Map;
import java.util.Optional;

/**
 * A Channel record of an MCAP file.
 *
 * @param id the channel id
 * @param topic its topic
 * @param messageEncoding its messages' encoding ({@code json} for prime-mcap files)
 * @param schema its schema, empty for schema id 0
 * @param metadata its metadata
 */
public record ChannelInfo(
    int id, String topic, String messageEncoding, Optional<SchemaInfo> schema, Map<String, String> metadata) {}
