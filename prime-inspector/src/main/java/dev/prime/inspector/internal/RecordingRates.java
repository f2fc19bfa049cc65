package dev.prime.inspector.internal;

import dev.prime.Recording;
import java.util.HashMap;
import java.util.LinkedHashMap;
import java.util.Map;

/**
 * Figures counted from a core's {@link Recording}: for every recorded name (the core's sources
 * and its chains made of a block), the values recorded per second between two samples. A
 * recording knows no processing times nor failures, so those figures are absent.
 */
public final class RecordingRates implements LiveFigures {
  private final Recording recording;
  private final Map<String, Long> lastCounts = new HashMap<>();
  private final SamplingClock clock = new SamplingClock();

  /**
   * @param recording the core's recording
   */
  public RecordingRates(Recording recording) {
    this.recording = recording;
  }

  @Override
  public Map<String, NodeFigures> sample() {
    double seconds = clock.secondsSinceLast();
    Map<String, NodeFigures> figures = new LinkedHashMap<>();
    for (String name : recording.names()) {
      long count = recording.recorded(name);
      Long before = lastCounts.put(name, count);
      double rate = before == null || seconds <= 0 ? 0 : (count - before) / seconds;
      figures.put(name, NodeFigures.counted(rate, count));
    }
    return figures;
  }

  @Override
  public String description() {
    return "Rates counted from the recording (values recorded per second, per source and chain);"
        + " processing times and failures need the core's metrics (CoreConfig.builder().metrics(true)).";
  }
}
