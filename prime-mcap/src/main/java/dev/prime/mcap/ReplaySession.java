package dev.prime.mcap;

import dev.prime.PrimeClock;
import java.io.Closeable;
import java.io.IOException;
import java.nio.file.Path;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Collection;
import java.util.Comparator;
import java.util.Iterator;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.stream.Stream;

/**
 * A replay in progress ({@link McapReplay#open()}): each {@link #feedNext()} publishes the next
 * recorded value to its event block. Messages are read lazily, chunk by chunk; messages with equal
 * log times are gathered and ordered by sequence number (then file order) before any is fed. At
 * recorded speed, the first value is fed at once and each later one when its log time's distance
 * from the first has passed on the options' clock since then (a caller slower than the recording
 * is never made to wait). Not thread-safe: one thread feeds.
 */
public final class ReplaySession implements Closeable {
  private static final Comparator<McapMessage> BY_SEQUENCE =
      Comparator.comparingLong(McapMessage::sequence);

  private final Path file;
  private final McapReader reader;
  private final Stream<McapMessage> stream;
  private final Iterator<McapMessage> messages;
  private final Map<String, McapReplay.Feed<?>> feeds;
  private final Map<String, Long> fed = new LinkedHashMap<>();
  private final ReplayOptions options;
  private final ArrayDeque<McapMessage> ready = new ArrayDeque<>();
  private McapMessage lookahead;
  private long firstLogTime = -1;
  private long startNanos;

  private ReplaySession(
      Path file,
      McapReader reader,
      Map<String, McapReplay.Feed<?>> feeds,
      Collection<String> order,
      ReplayOptions options) {
    this.file = file;
    this.reader = reader;
    this.feeds = feeds;
    this.options = options;
    order.forEach(channel -> fed.put(channel, 0L));
    this.stream = reader.messages().filter(m -> feeds.containsKey(m.channel().topic()));
    this.messages = stream.iterator();
  }

  static ReplaySession open(
      Path file,
      Map<String, McapReplay.Feed<?>> feeds,
      Collection<String> order,
      ReplayOptions options)
      throws IOException {
    McapReader reader = McapReader.open(file);
    try {
      List<String> missing = new ArrayList<>();
      for (String channel : order) {
        if (reader.channel(channel).isEmpty()) {
          missing.add(channel);
        }
      }
      if (!missing.isEmpty()) {
        throw new IllegalArgumentException(
            "cannot replay " + file + ": no channel " + missing + " in it; its channels: "
                + reader.channels().stream().map(ChannelInfo::topic).toList());
      }
      return new ReplaySession(file, reader, feeds, order, options);
    } catch (RuntimeException e) {
      reader.close();
      throw e;
    }
  }

  /**
   * Publishes the next recorded value (waiting for its time first, at recorded speed).
   *
   * @return the message fed, its value decoded; empty when every value has been fed
   * @throws IllegalArgumentException if the message does not decode into its channel's type
   * @throws InterruptedException if interrupted while waiting at recorded speed
   */
  public Optional<TypedMessage<Object>> feedNext() throws InterruptedException {
    McapMessage next = next();
    if (next == null) {
      return Optional.empty();
    }
    pace(next.logTime());
    String channel = next.channel().topic();
    Object value = feeds.get(channel).publishDecoded(next, file);
    fed.merge(channel, 1L, Long::sum);
    return Optional.of(
        new TypedMessage<>(channel, next.sequence(), next.logTime(), next.publishTime(), value));
  }

  /** {@return the values fed so far per channel} */
  public ReplayResult result() {
    return new ReplayResult(fed);
  }

  /** Closes the file; values not fed yet are not. */
  @Override
  public void close() throws IOException {
    stream.close();
    reader.close();
  }

  private McapMessage next() {
    if (ready.isEmpty()) {
      McapMessage first = lookahead != null ? lookahead : (messages.hasNext() ? messages.next() : null);
      lookahead = null;
      if (first == null) {
        return null;
      }
      List<McapMessage> group = new ArrayList<>();
      group.add(first);
      while (messages.hasNext()) {
        McapMessage m = messages.next();
        if (m.logTime() != first.logTime()) {
          lookahead = m;
          break;
        }
        group.add(m);
      }
      group.sort(BY_SEQUENCE); // stable: equal sequences stay in file order
      ready.addAll(group);
    }
    return ready.poll();
  }

  private void pace(long logTime) throws InterruptedException {
    Optional<PrimeClock> pacing = options.pacing();
    if (pacing.isEmpty()) {
      return;
    }
    PrimeClock clock = pacing.get();
    if (firstLogTime < 0) {
      firstLogTime = logTime;
      startNanos = clock.nanoTime();
      return;
    }
    long due = startNanos + (logTime - firstLogTime);
    if (due - clock.nanoTime() > 0) {
      // until the deadline, not for the difference: a clock moved meanwhile (a VirtualClock
      // advanced by another thread) would make a sleep for the difference overshoot
      clock.sleepUntil(due);
    }
  }
}
