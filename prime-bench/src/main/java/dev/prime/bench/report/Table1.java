package dev.prime.bench.report;

import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import org.openjdk.jmh.results.RunResult;
import org.openjdk.jmh.runner.RunnerException;
import org.openjdk.jmh.runner.options.VerboseMode;

/**
 * The command that runs the suite and writes the paper's Table 1 for the JVM:
 * {@code table1.json} (JMH's JSON, each result with its environment), {@code table1.md} (the
 * Markdown tables) and one PNG chart per table.
 *
 * <pre>
 * java -cp prime-bench/target/benchmarks.jar dev.prime.bench.report.Table1 quick|full|smoke DIR
 * java -cp prime-bench/target/benchmarks.jar dev.prime.bench.report.Table1 report DIR
 * </pre>
 *
 * <p>{@code report} rebuilds the Markdown and the charts from an existing {@code DIR/table1.json}.
 */
public final class Table1 {
  /** The raw results' file name. */
  public static final String JSON = "table1.json";

  /** The Markdown tables' file name. */
  public static final String MARKDOWN = "table1.md";

  private Table1() {}

  /**
   * Runs the suite or rebuilds the report.
   *
   * @param args mode ({@code quick}, {@code full}, {@code smoke} or {@code report}) and output
   *     directory
   * @throws IOException if a file cannot be written
   * @throws RunnerException if a benchmark fails
   */
  public static void main(String[] args) throws IOException, RunnerException {
    if (args.length != 2) {
      System.err.println("usage: Table1 quick|full|smoke|report OUTPUT_DIR");
      System.exit(2);
    }
    System.setProperty("java.awt.headless", "true");
    Path directory = Path.of(args[1]);
    Files.createDirectories(directory);
    if (!args[0].equals("report")) {
      RunSettings settings = RunSettings.named(args[0]);
      Environment environment = Environment.capture();
      List<RunResult> results = SuiteRunner.run(Families.ALL, settings, VerboseMode.NORMAL);
      String json = ResultsFile.annotate(SuiteRunner.json(results), environment.finished());
      Files.writeString(directory.resolve(JSON), json, StandardCharsets.UTF_8);
    }
    for (Path written : report(directory.resolve(JSON), directory)) {
      System.out.println("wrote " + written);
    }
  }

  /**
   * Writes the Markdown tables and the charts of a results file.
   *
   * @param json the results
   * @param directory where to write
   * @return the files written: the Markdown, then the charts
   * @throws IOException if a file cannot be read or written
   */
  public static List<Path> report(Path json, Path directory) throws IOException {
    List<ResultTable> tables = ResultTable.build(Families.ALL, ResultsFile.read(json));
    StringBuilder markdown =
        new StringBuilder(MarkdownTables.render(tables, ResultsFile.environment(json)));
    List<Path> charts = Charts.writePng(tables, directory);
    for (Path chart : charts) {
      markdown.append("![").append(chart.getFileName()).append("](")
          .append(chart.getFileName()).append(")\n\n");
    }
    Path md = directory.resolve(MARKDOWN);
    Files.writeString(md, markdown.toString(), StandardCharsets.UTF_8);
    List<Path> written = new ArrayList<>();
    written.add(md);
    written.addAll(charts);
    return written;
  }
}
