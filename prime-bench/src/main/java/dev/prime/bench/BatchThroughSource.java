package dev.prime.bench;

import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.List;
import java.util.Optional;

/**
 * One batch through an Optimus flow, as the flow benchmarks measure it: publish a batch, then take
 * one batch's worth of outputs (the batch published before, so the service always has work).
 */
final class BatchThroughSource {
  /** How long one output may take before the benchmark fails instead of hanging. */
  static final Duration TAKE_TIMEOUT = Duration.ofSeconds(30);

  private BatchThroughSource() {}

  /**
   * Publishes {@code batch} to {@code input}, then takes {@code batch.size()} values of {@code
   * output}.
   *
   * @param core the core that publishes
   * @param input the flow's source
   * @param batch the values published together
   * @param output a reader of the flow's outputs
   * @param what the flow, for the failure's message
   * @return the bytes taken (give them to JMH)
   * @throws InterruptedException if interrupted while taking
   * @throws IllegalStateException if an output does not come within {@link #TAKE_TIMEOUT}
   */
  static long pass(
      OptimusCore core, Source<byte[]> input, List<byte[]> batch, Reader<byte[]> output,
      String what) throws InterruptedException {
    core.publishAll(input, batch);
    long bytes = 0;
    for (int i = 0; i < batch.size(); i++) {
      Optional<byte[]> value = output.take(TAKE_TIMEOUT);
      if (value.isEmpty()) {
        throw new IllegalStateException("a value did not come through " + what + " within " + TAKE_TIMEOUT);
      }
      bytes += value.get().length;
    }
    return bytes;
  }
}
