package dev.prime.bench.report;

/**
 * One throughput target judged against a run.
 *
 * @param item the issue item the target belongs to, e.g. {@code in-memory hand-off}
 * @param target what must hold, in words, e.g. {@code Prime sources ≤ 2× the Disruptor, 100 B}
 * @param measured the figures the verdict rests on, in words
 * @param outcome met, not met, or not measured (a benchmark missing from the run)
 */
public record TargetVerdict(String item, String target, String measured, Outcome outcome) {

  /** A target's outcome in one run. */
  public enum Outcome {
    /** The run's figures meet the target. */
    MET("met"),
    /** The run's figures miss it. */
    NOT_MET("**not met**"),
    /** The run holds no result for a benchmark the target needs. */
    NOT_MEASURED("**not measured**");

    private final String words;

    Outcome(String words) {
      this.words = words;
    }

    /**
     * The outcome as the report writes it.
     *
     * @return the words
     */
    public String words() {
      return words;
    }
  }
}
