package dev.prime.mcap;

import com.fasterxml.jackson.databind.JsonNode;
import dev.prime.mcap.internal.JsonCodec;
import java.io.IOException;
import java.nio.charset.StandardCharsets;

/**
 * A Message record with its channel, as read: the data is not decoded until asked.
 *
 * @param channel its channel
 * @param sequence its sequence number (0..2^32-1)
 * @param logTime log time, nanoseconds
 * @param publishTime publish time, nanoseconds
 * @param data the message bytes
 */
public record McapMessage(ChannelInfo channel, long sequence, long logTime, long publishTime, byte[] data) {
  /** @return the data as UTF-8 text */
  public String text() {
    return new String(data, StandardCharsets.UTF_8);
  }

  /**
   * @return the data parsed as JSON, whatever its schema
   * @throws IllegalArgumentException if the channel is not JSON or the data is not JSON
   */
  public JsonNode json() {
    requireJson();
    try {
      return JsonCodec.MAPPER.readTree(data);
    } catch (IOException e) {
      throw new IllegalArgumentException(
          "message " + sequence + " on '" + channel.topic() + "' is not valid JSON: " + e.getMessage(), e);
    }
  }

  /**
   * @param type the type to decode into (the caller's choice: nothing in the file names a class)
   * @param <T> the type
   * @return the decoded value
   * @throws IllegalArgumentException if the channel is not JSON or the data is not a {@code T}
   */
  public <T> T decode(ValueType<T> type) {
    requireJson();
    try {
      return type.fromJson(data);
    } catch (IllegalArgumentException e) {
      throw new IllegalArgumentException(
          "message " + sequence + " on '" + channel.topic() + "' (schema "
              + channel.schema().map(SchemaInfo::name).orElse("none") + "): " + e.getMessage(), e);
    }
  }

  private void requireJson() {
    if (!McapWriter.MESSAGE_ENCODING.equals(channel.messageEncoding())) {
      throw new IllegalArgumentException(
          "channel '" + channel.topic() + "' has message encoding '" + channel.messageEncoding()
              + "'; only 'json' messages decode here (read the bytes with data())");
    }
  }
}
