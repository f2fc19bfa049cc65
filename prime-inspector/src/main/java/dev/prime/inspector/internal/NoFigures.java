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
    return "No live figures: this core has neither metrics nor a recording. Turn metrics on"
        + " (CoreConfig.builder().metrics(true)) to see rates, processing times and failures.";
  }
}
