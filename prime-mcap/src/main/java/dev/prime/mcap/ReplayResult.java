package dev.prime.mcap;

import java.util.Collections;
import java.util.LinkedHashMap;
import java.util.Map;
import java.util.Objects;

/**
 * What a replay fed.
 *
 * @param fed the values fed per channel, in the order the channels were named to the replay
 *     (a channel with no message in the file counts 0)
 */
public record ReplayResult(Map<String, Long> fed) {

  /**
   * Copies {@code fed}, keeping its order.
   *
   * @param fed the values fed per channel
   */
  public ReplayResult {
    fed = Collections.unmodifiableMap(new LinkedHashMap<>(Objects.requireNonNull(fed, "fed")));
  }

  /**
   * @param channel a channel the replay fed
   * @return the values fed from it
   * @throws IllegalArgumentException if the replay did not feed that channel
   */
  public long fed(String channel) {
    Long count = fed.get(channel);
    if (count == null) {
      throw new IllegalArgumentException(
          "'" + channel + "' was not replayed; replayed channels: " + fed.keySet());
    }
    return count;
  }

  /** {@return the values fed from every channel} */
  public long total() {
    return fed.values().stream().mapToLong(Long::longValue).sum();
  }
}
