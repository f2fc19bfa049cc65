package dev.prime;

import java.time.Instant;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;

/**
 * Where a core records (see {@link Recording}): the model compiler asks it for a tap at each
 * recorded point of the model as the point is compiled. A core whose recording is off has no
 * {@code RecordingPoints}, so nothing is compiled in and nothing runs per value.
 *
 * <p>Recorded points: every {@code BlockChain} (the tap wraps the chain's block, so it runs
 * wherever the media runs that block: in the caller's thread, in a fused class, or in the Optimus
 * process hosting the service) and every {@code EventSource} (subscribers to its event block
 * around the media's: see {@link #beforeSource}).
 */
final class RecordingPoints {
  private final PrimeCore core;
  private final InProcessServices unsubscriber; // closes its event block subscriptions at close
  private final Recording recording;
  private final Map<String, RecordingRing> eventSources = new ConcurrentHashMap<>();

  RecordingPoints(PrimeCore core, RecordingOptions options, InProcessServices memory) {
    this.core = core;
    this.unsubscriber = memory;
    this.recording = new Recording(core.name(), options, core::isClosed);
  }

  Recording recording() {
    return recording;
  }

  /** The block of a recorded chain: runs {@code block} and records each non-null output. */
  <I, O> Block<I, O> chain(String name, Block<I, O> block) {
    return new Tap<>(recording.ring(name, core.topologyRecorder().pseudoname(name)), block);
  }

  /**
   * Starts recording what {@code events} publishes, around the media's own subscriber: call it
   * before the media subscribes, then {@link SourcePoint#afterMedia()} once it has (or {@link
   * SourcePoint#cancel()} if the media made no source). Each value is stamped as its publish
   * begins and stored, with that stamp, after the media accepted it (a publish the media refuses
   * is not recorded). Stamping first keeps causality across processes: a value that a service
   * elsewhere computed from this one is stamped after it.
   */
  <T> SourcePoint beforeSource(String name, EventBlock<T> events) {
    return new SourcePoint(name, events);
  }

  /**
   * Records {@code values} that the media published to the event source {@code name} together,
   * not through its event block ({@link PrimeCore#publishedTogether}), each stamped with the time
   * that publish began; nothing for a name that is not a recorded event source, or once the core
   * is closed.
   */
  void recordAll(String name, List<?> values, Instant wallTime, long monotonicNanos) {
    RecordingRing ring = eventSources.get(name);
    if (ring == null || core.isClosed()) {
      return;
    }
    for (Object value : values) {
      ring.record(value, wallTime, monotonicNanos);
    }
  }

  /** The recording of one event source; see {@link #beforeSource}. */
  final class SourcePoint {
    private final String name;
    private final EventBlock<?> events;
    private final ThreadLocal<Stamp> stamps = ThreadLocal.withInitial(Stamp::new);
    private final EventBlock.Subscription stamping;

    private SourcePoint(String name, EventBlock<?> events) {
      this.name = name;
      this.events = events;
      this.stamping =
          events.subscribe(
              value -> {
                Stamp stamp = stamps.get();
                stamp.value = value;
                stamp.wallTime = Instant.now();
                stamp.monotonicNanos = System.nanoTime();
              });
    }

    /**
     * Subscribes the recording subscriber, after the media's; both subscribers leave the event
     * block when the core closes.
     */
    void afterMedia() {
      RecordingRing ring = recording.ring(name, core.topologyRecorder().pseudoname(name));
      eventSources.put(name, ring);
      unsubscriber.unsubscribeOnClose(stamping);
      EventBlock.Subscription recorder =
          events.subscribe(
              value -> {
                if (core.isClosed()) {
                  return;
                }
                Stamp stamp = stamps.get();
                if (stamp.value == value) { // not overwritten by a nested publish of this thread
                  stamp.value = null;
                  ring.record(value, stamp.wallTime, stamp.monotonicNanos);
                } else {
                  ring.record(value);
                }
              });
      unsubscriber.unsubscribeOnClose(recorder);
    }

    /** Stops stamping: the media made no source. */
    void cancel() {
      stamping.close();
    }
  }

  /** When this thread's current publish began. */
  private static final class Stamp {
    Object value;
    Instant wallTime;
    long monotonicNanos;
  }

  /** A chain's block with its output recorded. */
  private record Tap<I, O>(RecordingRing ring, Block<I, O> block) implements Block<I, O> {
    @Override
    public O process(I input) {
      O output = block.process(input);
      if (output != null) {
        ring.record(output);
      }
      return output;
    }
  }
}
