package dev.prime;

/**
 * Where a core records (see {@link Recording}): the model compiler asks it for a tap at each
 * recorded point of the model as the point is compiled. A core whose recording is off has no
 * {@code RecordingPoints}, so nothing is compiled in and nothing runs per value.
 *
 * <p>Recorded points: every {@code BlockChain} (the tap wraps the chain's block, so it runs
 * wherever the media runs that block: in the caller's thread, in a fused class, or in the Optimus
 * process hosting the service) and every {@code EventSource} (a subscriber to its event block,
 * subscribed after the media's, so a publish the media refuses is not recorded).
 */
final class RecordingPoints {
  private final PrimeCore core;
  private final Recording recording;

  RecordingPoints(PrimeCore core, RecordingOptions options) {
    this.core = core;
    this.recording = new Recording(core.name(), options);
  }

  Recording recording() {
    return recording;
  }

  /** The block of a recorded chain: runs {@code block} and records each non-null output. */
  <I, O> Block<I, O> chain(String name, Block<I, O> block) {
    return new Tap<>(recording.ring(name, core.topologyRecorder().pseudoname(name)), block);
  }

  /** Records what {@code events} publishes from now on, while the core is open. */
  <T> void source(String name, EventBlock<T> events) {
    RecordingRing ring = recording.ring(name, core.topologyRecorder().pseudoname(name));
    events.subscribe(
        value -> {
          if (!core.isClosed()) {
            ring.record(value);
          }
        });
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
