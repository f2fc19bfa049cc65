package dev.prime.inspector.internal;

import dev.prime.Metrics;
import dev.prime.ServiceMetrics;
import java.util.HashMap;
import java.util.LinkedHashMap;
import java.util.Map;

/**
 * Figures from a core's {@link Metrics}: for every metered node, the values it took per second
 * and its mean processing time over the last sampling period, its failures, dead letters, queue
 * depth and missed values.
 */
public final class MetricsFigures implements LiveFigures {
  private final Metrics metrics;
  private final Map<String, ServiceMetrics> last = new HashMap<>();
  private final Map<String, Boolean> queues = new HashMap<>(); // structure: asked once per node
  private final SamplingClock clock = new SamplingClock();

  /**
   * @param metrics the core's metrics
   */
  public MetricsFigures(Metrics metrics) {
    this.metrics = metrics;
  }

  @Override
  public Map<String, NodeFigures> sample() {
    double seconds = clock.secondsSinceLast();
    Map<String, NodeFigures> figures = new LinkedHashMap<>();
    for (ServiceMetrics service : metrics.services()) {
      ServiceMetrics before = last.put(service.name(), service);
      double rate =
          before == null || seconds <= 0 ? 0 : (service.valuesIn() - before.valuesIn()) / seconds;
      long count = service.processing().count();
      long nanos = service.processing().totalNanos();
      double latency = Double.NaN;
      if (before != null && count > before.processing().count()) {
        latency =
            (nanos - before.processing().totalNanos())
                / (double) (count - before.processing().count()) / 1e6;
      } else if (count > 0) {
        latency = service.processing().meanNanos() / 1e6;
      }
      figures.put(
          service.name(),
          new NodeFigures(
              rate,
              service.valuesIn(),
              latency,
              service.failures(),
              service.deadLetters(),
              service.queueDepth(),
              service.queueDepth() < 0
                  && queues.computeIfAbsent(service.name(), metrics::hasQueue),
              service.missed()));
    }
    return figures;
  }

  @Override
  public String description() {
    return "Figures from the core's metrics: values taken per second and the mean processing time"
        + " over the last half second, failures, and where the media has them dead letters, queue"
        + " depth (or that it cannot be read now) and missed values.";
  }
}
