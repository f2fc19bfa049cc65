package dev.prime.mcap;

import dev.prime.EventBlock;
import java.io.IOException;
import java.nio.file.Path;
import java.util.LinkedHashMap;
import java.util.Map;
import java.util.Objects;

/**
 * Feeds the values recorded in an MCAP file back into event blocks: each named channel feeds one
 * {@link EventBlock} (typically the event block of the source of that name in a fresh topology,
 * so the topology runs again on the recorded inputs). Values are decoded into the type the caller
 * names for the channel (never a type named by the file) and published in recorded order across
 * channels: by log time, equal log times by sequence number, then in file order. Channels of the
 * file that are not named are skipped.
 *
 * <pre>{@code
 * WheelEncoders encoders = new WheelEncoders(spec);      // a fresh topology on any media
 * RobotController.wire(core, encoders, spec, goal, dt);
 * core.start();
 * ReplayResult result = McapReplay.of(Path.of("run.mcap"))
 *     .feed("encoders", encoders.events(), EncoderReading.class)
 *     .options(ReplayOptions.recordedSpeed())
 *     .run();
 * result.fed("encoders");                                  // values fed
 * }</pre>
 *
 * <p>{@link #run()} feeds everything; {@link #open()} gives a {@link ReplaySession} that feeds one
 * value per call, for a caller that acts between values (a control loop that waits for each
 * output). A replay object is a description: each {@code run} or {@code open} reads the file anew.
 * It is not thread-safe; configure it in one thread.
 */
public final class McapReplay {
  private final Path file;
  private final Map<String, Feed<?>> feeds = new LinkedHashMap<>();
  private ReplayOptions options = ReplayOptions.asFastAsPossible();

  /** One channel's target and type. */
  record Feed<T>(String channel, EventBlock<? super T> target, ValueType<T> type) {
    Object publishDecoded(McapMessage message, Path file) {
      T value;
      try {
        value = message.decode(type);
      } catch (IllegalArgumentException e) {
        throw new IllegalArgumentException(
            "replaying " + file + ": message " + message.sequence() + " of channel '" + channel
                + "' (log time " + message.logTime() + ") does not decode as " + type.name()
                + "; name the channel's recorded type in feed(...): " + e.getMessage(),
            e);
      }
      target.publish(value);
      return value;
    }
  }

  private McapReplay(Path file) {
    this.file = Objects.requireNonNull(file, "file must not be null");
  }

  /**
   * A replay of one MCAP file; name the channels to feed with {@link #feed}.
   *
   * @param file the file (written by {@link RecordingMcap} or any MCAP writer with JSON messages)
   * @return a replay feeding nothing yet
   */
  public static McapReplay of(Path file) {
    return new McapReplay(file);
  }

  /**
   * Feeds the values of a channel to an event block.
   *
   * @param channel the channel's topic (for a recording: the service name)
   * @param target the event block to publish them to
   * @param type the values' class
   * @param <T> the values' type
   * @return this replay
   * @throws IllegalArgumentException if the channel is already fed, or the class cannot be a
   *     channel's type
   */
  public <T> McapReplay feed(String channel, EventBlock<? super T> target, Class<T> type) {
    return feed(channel, target, ValueType.of(Objects.requireNonNull(type, "type must not be null")));
  }

  /**
   * Feeds the values of a channel to an event block, decoding them into a (generic) type.
   *
   * @param channel the channel's topic (for a recording: the service name)
   * @param target the event block to publish them to
   * @param type the values' type, e.g. {@code new ValueType<List<Pose>>() {}}
   * @param <T> the values' type
   * @return this replay
   * @throws IllegalArgumentException if the channel is already fed
   */
  public <T> McapReplay feed(String channel, EventBlock<? super T> target, ValueType<T> type) {
    Objects.requireNonNull(channel, "channel must not be null");
    Objects.requireNonNull(target, "target must not be null");
    Objects.requireNonNull(type, "type must not be null");
    if (feeds.containsKey(channel)) {
      throw new IllegalArgumentException(
          "channel '" + channel + "' is already fed; each channel feeds one event block");
    }
    feeds.put(channel, new Feed<>(channel, target, type));
    return this;
  }

  /**
   * Sets the pace.
   *
   * @param options {@link ReplayOptions#asFastAsPossible()} (the default) or {@link
   *     ReplayOptions#recordedSpeed()}
   * @return this replay
   */
  public McapReplay options(ReplayOptions options) {
    this.options = Objects.requireNonNull(options, "options must not be null");
    return this;
  }

  /**
   * Feeds every value of the named channels, in recorded order, on the calling thread (each
   * value's subscribers run before the next is fed).
   *
   * @return the values fed per channel
   * @throws IOException if the file cannot be read
   * @throws McapFormatException if the file is malformed
   * @throws IllegalArgumentException if a named channel is not in the file (the message lists the
   *     file's channels) or a message does not decode into its channel's type (the message names
   *     the channel and the message)
   * @throws IllegalStateException if no channel was named
   * @throws InterruptedException if interrupted while waiting at recorded speed
   */
  public ReplayResult run() throws IOException, InterruptedException {
    try (ReplaySession session = open()) {
      while (session.feedNext().isPresent()) {
        // each call feeds one value
      }
      return session.result();
    }
  }

  /**
   * Opens the file and checks that every named channel is in it; nothing is fed yet.
   *
   * @return a session that feeds one value per {@link ReplaySession#feedNext()}
   * @throws IOException if the file cannot be read
   * @throws McapFormatException if the file is malformed
   * @throws IllegalArgumentException if a named channel is not in the file; the message lists
   *     the missing ones and the file's channels
   * @throws IllegalStateException if no channel was named
   */
  public ReplaySession open() throws IOException {
    if (feeds.isEmpty()) {
      throw new IllegalStateException(
          "nothing to replay from " + file + ": name the channels to feed with feed(channel,"
              + " eventBlock, type)");
    }
    return ReplaySession.open(file, Map.copyOf(feeds), feeds.keySet(), options);
  }
}
