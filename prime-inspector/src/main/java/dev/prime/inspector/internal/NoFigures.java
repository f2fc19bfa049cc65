package dev.prime.inspector.internal;

import java.util.Map;

/** No figures: a core with neither metrics nor a recording. */
public final class NoFigures implements LiveFigures {
  @Override
  public Map<String, NodeFigures> sample() {
    return Map.of();
  }

  @Override
  public String description() {
    return "No live figures: this core records nothing and has no metrics. Turn recording on"
        + " (CoreConfig.builder().recording(RecordingOptions.defaults())) to see rates.";
  }
}
