package dev.prime.bench.report;

import dev.prime.bench.report.TargetVerdict.Outcome;
import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import java.util.Map;
import java.util.Optional;
import org.openjdk.jmh.profile.GCProfiler;
import org.openjdk.jmh.results.RunResult;
import org.openjdk.jmh.runner.NoBenchmarksException;
import org.openjdk.jmh.runner.Runner;
import org.openjdk.jmh.runner.RunnerException;
import org.openjdk.jmh.runner.options.ChainedOptionsBuilder;
import org.openjdk.jmh.runner.options.OptionsBuilder;
import org.openjdk.jmh.runner.options.TimeValue;

/**
 * The command that runs the throughput targets' benchmarks and judges each target: the in-memory
 * hand-off against the Disruptor, Kotlin Channels and Reactor (5 forks of Prime and of the
 * Disruptor, so the spread across forks shows, and 5 of a bare core-to-core round trip, {@link
 * dev.prime.bench.CoreRoundTripBenchmark}, to show the machine's own), the synchronous sources
 * row (and its floor, the round trip carrying the row's packet), Optimus flows and calls against
 * raw Jedis (the calls in alternated rounds, {@link #CALL_ROUNDS}), and competing consumers with
 * 1, 2 and 3 hosts. Writes {@code targets.json} (JMH's JSON, each result with its environment)
 * and {@code targets.md} (one line per target: target, figures,
 * verdict), followed by figures reported for information and not judged: the earlier Prime row
 * {@code AsyncHandOffBenchmark.primeSourceAndReader} (two thread hand-offs, the outputs read back
 * with a {@code Reader}), the machine's spread across forks, and the synchronous row beside its
 * floor (see {@link #information}).
 *
 * <pre>
 * java -cp prime-bench/target/benchmarks.jar dev.prime.bench.report.ThroughputTargets run DIR
 * java -cp prime-bench/target/benchmarks.jar dev.prime.bench.report.ThroughputTargets report DIR
 * </pre>
 *
 * <p>{@code report} judges an existing {@code DIR/targets.json} again. About 14 minutes on 2 cores.
 */
public final class ThroughputTargets {
  /** The raw results' file name. */
  public static final String JSON = "targets.json";

  /** The verdicts' file name. */
  public static final String MARKDOWN = "targets.md";

  /** The payloads the in-memory targets hold at. */
  static final List<String> PAYLOADS = List.of("100", "1024", "10240");

  private static final String HAND_OFF = "in-memory hand-off";
  private static final String FRAMES = "Optimus frames";
  private static final String CONSUMERS = "competing consumers";

  private ThroughputTargets() {}

  /**
   * Runs the benchmarks and judges them, or judges an existing run.
   *
   * @param args {@code run} or {@code report}, and the output directory
   * @throws IOException if a file cannot be read or written
   * @throws RunnerException if a benchmark fails
   */
  public static void main(String[] args) throws IOException, RunnerException {
    if (args.length != 2 || !(args[0].equals("run") || args[0].equals("report"))) {
      System.err.println("usage: ThroughputTargets run|report OUTPUT_DIR");
      System.exit(2);
    }
    Path directory = Path.of(args[1]);
    Files.createDirectories(directory);
    Path json = directory.resolve(JSON);
    if (args[0].equals("run")) {
      Environment environment = Environment.capture();
      List<RunResult> results = new ArrayList<>();
      for (ChainedOptionsBuilder options : runs()) {
        try {
          results.addAll(new Runner(options.shouldFailOnError(true).build()).run());
        } catch (NoBenchmarksException absent) {
          // judged "not measured" below: the other groups' results still count
          System.err.println("no benchmark in this jar matches one group of the targets: "
              + absent.getMessage());
        }
      }
      String annotated = ResultsFile.annotate(SuiteRunner.json(results), environment.finished());
      Files.writeString(json, annotated, StandardCharsets.UTF_8);
    }
    List<Score> scores = Score.readAll(json);
    String markdown =
        render(judge(scores), ResultsFile.environment(json)) + "\n" + information(scores);
    Files.writeString(directory.resolve(MARKDOWN), markdown, StandardCharsets.UTF_8);
    System.out.print(markdown);
  }

  /**
   * The order of the call rounds: Optimus's call and the raw echo loop alternate, one fork a
   * round, so that each sits as often before the other as after it. The machine changes speed by
   * itself within minutes; run one after the other (as they were before, minutes apart within
   * one JMH run) the two were compared across whatever the machine did between them. The ratio is
   * judged on the rounds' means ({@link #pooled}).
   */
  static final List<String> CALL_ROUNDS =
      List.of("optimusCall", "rawCall", "rawCall", "optimusCall", "optimusCall", "rawCall");

  /** One JMH run per group of benchmarks, each with the forks its targets need. */
  private static List<ChainedOptionsBuilder> runs() {
    String[] payloads = PAYLOADS.toArray(String[]::new);
    List<ChainedOptionsBuilder> runs = new ArrayList<>(List.of(
        timed("AsyncHandOffBenchmark\\.primeSource$", 5, 3, 1000, 5, 1000)
            .param("payload", payloads).param("scenario", "monomorphic").param("length", "4")
            .addProfiler(GCProfiler.class),
        // the Disruptor with as many forks as Prime: its own spread across forks is the machine's
        timed("AsyncHandOffBenchmark\\.disruptor$", 5, 3, 1000, 5, 1000)
            .param("payload", payloads).param("scenario", "monomorphic").param("length", "4"),
        timed("AsyncHandOffBenchmark\\.(kotlinChannel|reactorPublishOn|primeSourceAndReader)$",
            2, 3, 1000, 5, 1000)
            .param("payload", payloads).param("scenario", "monomorphic").param("length", "4"),
        // the bare round trip, and the same carrying the synchronous row's packet (its floor)
        timed("CoreRoundTripBenchmark\\.roundTrip(WithPacket)?$", 5, 3, 1000, 5, 1000),
        timed("SyncSourceBenchmark\\.primeSource$", 1, 3, 500, 5, 1000)
            .param("payload", payloads).param("scenario", "monomorphic").param("length", "4")
            .addProfiler(GCProfiler.class),
        timed("OptimusBenchmark\\.(optimusFlow|rawFlow)$", 1, 2, 2000, 5, 2000)
            .param("payload", "100").param("scenario", "1hop", "4hops")));
    for (String call : CALL_ROUNDS) {
      runs.add(timed("OptimusBenchmark\\." + call + "$", 1, 2, 2000, 5, 2000)
          .param("payload", "100").param("scenario", "1hop", "4hops"));
    }
    runs.add(timed("CompetingConsumersBenchmark\\.", 1, 2, 2000, 5, 2000));
    return runs;
  }

  private static ChainedOptionsBuilder timed(
      String include, int forks, int warmups, int warmupMillis, int iterations,
      int iterationMillis) {
    return new OptionsBuilder()
        .include(include)
        .forks(forks)
        .warmupIterations(warmups)
        .warmupTime(TimeValue.milliseconds(warmupMillis))
        .measurementIterations(iterations)
        .measurementTime(TimeValue.milliseconds(iterationMillis));
  }

  /**
   * Judges every target against a run's results.
   *
   * @param scores the run's results
   * @return one verdict per target, in the order
   */
  public static List<TargetVerdict> judge(List<Score> scores) {
    List<TargetVerdict> verdicts = new ArrayList<>();
    for (String payload : PAYLOADS) {
      Map<String, String> at = Map.of("payload", payload, "scenario", "monomorphic");
      String bytes = bytesName(payload);
      Optional<Score> prime = find(scores, "AsyncHandOffBenchmark.primeSource", at);
      verdicts.add(prime.map(p -> stable(p, bytes))
          .orElse(missing(HAND_OFF, "slowest fork of Prime sources ≤ 1.5× the fastest, " + bytes)));
      verdicts.add(compare(HAND_OFF, "Prime sources ≤ 2× the LMAX Disruptor, " + bytes, prime,
          find(scores, "AsyncHandOffBenchmark.disruptor", at), 2.0, true));
      verdicts.add(compare(HAND_OFF, "Kotlin Channels ≥ 1.5× Prime sources' time, " + bytes,
          find(scores, "AsyncHandOffBenchmark.kotlinChannel", at), prime, 1.5, false));
      verdicts.add(compare(HAND_OFF, "Reactor publishOn ≥ 1.5× Prime sources' time, " + bytes,
          find(scores, "AsyncHandOffBenchmark.reactorPublishOn", at), prime, 1.5, false));
      verdicts.add(prime.map(p -> allocation(p, bytes))
          .orElse(missing(HAND_OFF, "0 B allocated per value, " + bytes)));
      verdicts.add(find(scores, "SyncSourceBenchmark.primeSource", at)
          .map(s -> atMost(HAND_OFF, "synchronous Prime-sources row ≤ 0.4 µs, " + bytes, s, 400))
          .orElse(missing(HAND_OFF, "synchronous Prime-sources row ≤ 0.4 µs, " + bytes)));
    }
    verdicts.add(atLeast(FRAMES, "optimusFlow ≥ 400,000 values/s through one hop, 100 B",
        find(scores, "OptimusBenchmark.optimusFlow", Map.of("payload", "100", "scenario", "1hop")),
        400_000));
    verdicts.add(atLeast(FRAMES, "optimusFlow ≥ 150,000 values/s through four hops, 100 B",
        find(scores, "OptimusBenchmark.optimusFlow", Map.of("payload", "100", "scenario", "4hops")),
        150_000));
    for (String hops : List.of("1hop", "4hops")) {
      Map<String, String> at = Map.of("payload", "100", "scenario", hops);
      verdicts.add(compare(FRAMES, "optimusCall ≤ 1.1× the raw Jedis echo loop, " + hops + ", 100 B",
          pooled(scores, "OptimusBenchmark.optimusCall", at),
          pooled(scores, "OptimusBenchmark.rawCall", at), 1.1, true));
    }
    Optional<Score> one = find(scores, "CompetingConsumersBenchmark.hosted", Map.of("hosts", "1"));
    verdicts.add(speedUp("2", 1.8, one, scores));
    verdicts.add(speedUp("3", 2.6, one, scores));
    return verdicts;
  }

  /**
   * Figures reported for information, not judged: the earlier Prime hand-off row, {@code
   * primeSourceAndReader}, at each payload (two thread hand-offs per value where the judged rows
   * have one, so its time is not comparable with theirs); then the spread across forks of the
   * Disruptor and of {@link dev.prime.bench.CoreRoundTripBenchmark}, which no library's code
   * moves: how far this machine alone moves a hand-off from fork to fork; then the synchronous
   * row beside its floor, {@code CoreRoundTripBenchmark.roundTripWithPacket} (two bare threads
   * running the row's adders on its packet in turn, with no queue between them).
   *
   * @param scores the run's results
   * @return Markdown: three paragraphs, each a heading line and one line per figure
   */
  public static String information(List<Score> scores) {
    StringBuilder out = new StringBuilder(
        "For information, not judged: Prime sources with the outputs read back by a Reader"
            + " (`AsyncHandOffBenchmark.primeSourceAndReader`, two thread hand-offs per value):\n\n");
    for (String payload : PAYLOADS) {
      Map<String, String> at = Map.of("payload", payload, "scenario", "monomorphic");
      out.append("- ").append(bytesName(payload)).append(": ")
          .append(find(scores, "AsyncHandOffBenchmark.primeSourceAndReader", at)
              .map(ThroughputTargets::figure).orElse("no result in this run"))
          .append('\n');
    }
    out.append("\nFor information, not judged: the machine's own spread across forks in the same"
        + " run, to read the hand-off's beside (the LMAX Disruptor, and a round trip between two"
        + " spinning threads with no library at all, `CoreRoundTripBenchmark.roundTrip`):\n\n");
    for (String payload : PAYLOADS) {
      Map<String, String> at = Map.of("payload", payload, "scenario", "monomorphic");
      out.append("- the Disruptor, ").append(bytesName(payload)).append(": ")
          .append(find(scores, "AsyncHandOffBenchmark.disruptor", at)
              .filter(s -> s.forkMeans().size() >= 2)
              .map(ThroughputTargets::forks).orElse("fewer than 2 forks in this run"))
          .append('\n');
    }
    out.append("- a core-to-core round trip: ")
        .append(find(scores, "CoreRoundTripBenchmark.roundTrip", Map.of())
            .filter(s -> s.forkMeans().size() >= 2)
            .map(ThroughputTargets::forks).orElse("fewer than 2 forks in this run"))
        .append('\n');
    out.append("\nFor information, not judged: the synchronous row beside its floor on this machine"
        + " at this time, a round trip between two spinning threads with no library at all in"
        + " which the echo thread runs the row's four adders on the row's packet"
        + " (`CoreRoundTripBenchmark.roundTripWithPacket`):\n\n");
    Optional<Score> floor = find(scores, "CoreRoundTripBenchmark.roundTripWithPacket", Map.of());
    out.append("- the floor: ")
        .append(floor.map(f -> figure(f) + (f.forkMeans().size() >= 2 ? "; " + forks(f) : ""))
            .orElse("no result in this run"))
        .append('\n');
    for (String payload : PAYLOADS) {
      Map<String, String> at = Map.of("payload", payload, "scenario", "monomorphic");
      Optional<Score> row = find(scores, "SyncSourceBenchmark.primeSource", at);
      out.append("- the synchronous row, ").append(bytesName(payload)).append(": ")
          .append(row.map(r -> figure(r) + floor.map(f -> String.format(Locale.ROOT,
                  ", %.2f× the floor", r.value() / f.value())).orElse(""))
              .orElse("no result in this run"))
          .append('\n');
    }
    return out.toString();
  }

  private static TargetVerdict speedUp(
      String hosts, double wanted, Optional<Score> one, List<Score> scores) {
    String target = hosts + " hosts ≥ " + wanted + "× one host's values/s (a 1 ms block)";
    Optional<Score> many =
        find(scores, "CompetingConsumersBenchmark.hosted", Map.of("hosts", hosts));
    if (one.isEmpty() || many.isEmpty()) {
      return missing(CONSUMERS, target);
    }
    double ratio = many.get().value() / one.get().value();
    return new TargetVerdict(CONSUMERS, target,
        String.format(Locale.ROOT, "%s against %s: %.2f×",
            figure(many.get()), figure(one.get()), ratio),
        ratio >= wanted ? Outcome.MET : Outcome.NOT_MET);
  }

  /**
   * {@code subject} against {@code baseline}: with {@code atMost}, subject ≤ factor × baseline
   * (times); else subject ≥ factor × baseline.
   */
  private static TargetVerdict compare(
      String item, String target, Optional<Score> subject, Optional<Score> baseline,
      double factor, boolean atMost) {
    if (subject.isEmpty() || baseline.isEmpty()) {
      return missing(item, target);
    }
    double ratio = subject.get().value() / baseline.get().value();
    boolean met = atMost ? ratio <= factor : ratio >= factor;
    return new TargetVerdict(item, target,
        String.format(Locale.ROOT, "%s against %s: %.2f×",
            figure(subject.get()), figure(baseline.get()), ratio),
        met ? Outcome.MET : Outcome.NOT_MET);
  }

  private static TargetVerdict stable(Score prime, String bytes) {
    String target = "slowest fork of Prime sources ≤ 1.5× the fastest, " + bytes;
    if (prime.forkMeans().size() < 2) {
      return missing(HAND_OFF, target + " (needs at least 2 forks)");
    }
    return new TargetVerdict(HAND_OFF, target, forks(prime),
        spread(prime) <= 1.5 ? Outcome.MET : Outcome.NOT_MET);
  }

  /** The slowest fork's mean over the fastest's. */
  private static double spread(Score score) {
    List<Double> means = score.forkMeans();
    return means.stream().mapToDouble(Double::doubleValue).max().orElseThrow()
        / means.stream().mapToDouble(Double::doubleValue).min().orElseThrow();
  }

  /** Each fork's mean and the spread: "5 forks, ns: 25, 25, 49, 25, 25; 1.98×". */
  private static String forks(Score score) {
    return String.format(Locale.ROOT, "%d forks, ns: %s; %.2f×", score.forkMeans().size(),
        joined(score.forkMeans(), "%.0f"), spread(score));
  }

  /** Each mean in {@code format}, separated by commas. */
  private static String joined(List<Double> means, String format) {
    StringBuilder out = new StringBuilder();
    for (double mean : means) {
      out.append(out.length() == 0 ? "" : ", ").append(String.format(Locale.ROOT, format, mean));
    }
    return out.toString();
  }

  private static TargetVerdict allocation(Score prime, String bytes) {
    String target = "0 B allocated per value, " + bytes;
    if (Double.isNaN(prime.bytesPerOp())) {
      return missing(HAND_OFF, target + " (run without -prof gc)");
    }
    // JMH's normalised allocation carries the measurement's own noise: under 1 byte is none
    return new TargetVerdict(HAND_OFF, target,
        String.format(Locale.ROOT, "%.3f B/value", prime.bytesPerOp()),
        prime.bytesPerOp() < 1 ? Outcome.MET : Outcome.NOT_MET);
  }

  private static TargetVerdict atMost(String item, String target, Score score, double nanos) {
    return new TargetVerdict(item, target, figure(score),
        score.value() <= nanos ? Outcome.MET : Outcome.NOT_MET);
  }

  private static TargetVerdict atLeast(
      String item, String target, Optional<Score> score, double perSecond) {
    return score
        .map(s -> new TargetVerdict(item, target, figure(s),
            s.value() >= perSecond ? Outcome.MET : Outcome.NOT_MET))
        .orElse(missing(item, target));
  }

  private static TargetVerdict missing(String item, String target) {
    return new TargetVerdict(item, target, "no result in this run", Outcome.NOT_MEASURED);
  }

  private static Optional<Score> find(List<Score> scores, String method, Map<String, String> at) {
    return scores.stream().filter(s -> s.is(method, at)).findFirst();
  }

  /**
   * Every result of {@code method} at {@code at}, as one score: a benchmark run in rounds ({@link
   * #CALL_ROUNDS}) has one result per round. Its value is the mean of the rounds' means (each
   * round runs as long as the others), its fork means are the rounds' means in run order, and its
   * error is {@code NaN}: the rounds' means are shown instead. A single result is returned as it is, so
   * a run made before the rounds is judged as it was.
   *
   * @return the pooled score, or empty if the run has no result of {@code method} at {@code at}
   */
  static Optional<Score> pooled(List<Score> scores, String method, Map<String, String> at) {
    List<Score> rounds = scores.stream().filter(s -> s.is(method, at)).toList();
    if (rounds.size() <= 1) {
      return rounds.stream().findFirst();
    }
    List<Double> means = rounds.stream().map(Score::value).toList();
    double mean = means.stream().mapToDouble(Double::doubleValue).average().orElseThrow();
    Score first = rounds.get(0);
    return Optional.of(new Score(first.benchmark(), first.params(), mean, Double.NaN,
        first.throughput(), means, Double.NaN));
  }

  private static String figure(Score score) {
    if (Double.isNaN(score.error()) && score.forkMeans().size() > 1 && !score.throughput()) {
      return String.format(Locale.ROOT, "%,.1f ns (%d rounds: %s)", score.value(),
          score.forkMeans().size(), joined(score.forkMeans(), "%,.0f"));
    }
    return score.throughput()
        ? String.format(Locale.ROOT, "%,.0f ± %,.0f values/s", score.value(), score.error())
        : String.format(Locale.ROOT, "%,.1f ± %,.1f ns", score.value(), score.error());
  }

  private static String bytesName(String payload) {
    return switch (payload) {
      case "1024" -> "1 KB";
      case "10240" -> "10 KB";
      default -> payload + " B";
    };
  }

  /**
   * The verdicts as Markdown: the run's environment, then one table row per target.
   *
   * @param verdicts the verdicts
   * @param environment where and when the run took place, or {@code null} if unknown
   * @return the Markdown
   */
  public static String render(List<TargetVerdict> verdicts, Environment environment) {
    StringBuilder out = new StringBuilder();
    if (environment != null) {
      out.append(String.format(Locale.ROOT,
          "Run %s on %s (%d CPUs), %s, %s; 1-minute load %.2f before, %.2f after.%n%n",
          environment.date(), environment.cpuModel(), environment.cpus(), environment.jdk(),
          environment.os(), environment.loadBefore(), environment.loadAfter()));
    }
    long met = verdicts.stream().filter(v -> v.outcome() == Outcome.MET).count();
    out.append(String.format(Locale.ROOT, "%d of %d targets met.%n%n", met, verdicts.size()));
    out.append("| item | target | measured | verdict |\n|---|---|---|---|\n");
    for (TargetVerdict verdict : verdicts) {
      out.append("| ").append(verdict.item()).append(" | ").append(verdict.target())
          .append(" | ").append(verdict.measured()).append(" | ")
          .append(verdict.outcome().words()).append(" |\n");
    }
    return out.toString();
  }
}
