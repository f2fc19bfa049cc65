package dev.prime.bench.report;

import java.math.BigDecimal;
import java.math.RoundingMode;
import java.util.List;
import java.util.Locale;

/**
 * Writes result tables as Markdown, laid out like the paper's Table 1: microseconds per
 * transmission ± error and the ratio to the baseline (FOR) in every cell, then the same table of
 * allocation per transmission.
 */
public final class MarkdownTables {
  /**
   * The plain-words legend written above the tables: what a transmission, FOR, the scenarios, the
   * error and the allocation mean.
   */
  public static final String LEGEND =
      """
      How to read the tables:

      - **transmission**: one packet going in at the start of a chain of 4 blocks (each adds a \
      number to the packet) and coming out at its end. A cell is the mean time of one, in µs. In \
      the asynchronous hand-off rows (Prime sources, Kotlin Channels, Reactor publishOn, LMAX \
      Disruptor) a producer and a consumer thread overlap, so it is time per packet at full \
      throughput; in the Optimus tables it is one synchronous call through 1 or 4 services over \
      Redis.
      - **FOR**: the baseline row, the same 4 blocks called by hand-written Java \
      (`a4.process(a3.process(a2.process(a1.process(p))))`), no library at all. The ratio after \
      each time compares it with the baseline in the same column: 3.00× is three times as slow. \
      The Optimus tables' baseline is a raw Jedis echo loop on the same Redis.
      - **monomorphic**: the measured chain is the only chain in the JVM, so the JIT sees one \
      block class at every call site and can inline it all.
      - **polluted**: ten other chains (other lengths and block classes) are run in the same JVM \
      before and between the measurements, as in a controller with many chains, so call sites \
      that chains share have seen several block classes. Closer to a real program.
      - **recordingOff** / **recordingOn**: the synchronous rows in a core created with the \
      default settings (recording off: the rows must match the monomorphic synchronous table) and \
      with `RecordingOptions.defaults()` (every block's output and every published packet stamped \
      and kept in a ring of 10,000 per name).
      - **payload**: bytes each packet carries (100 B, 1 KB, 10 KB); nothing local copies them.
      - **± error**: JMH's 99.9 % confidence interval of the mean. When it is as large as the \
      time itself, the cell is noise: read the rows that agree across the three columns.
      - **bytes allocated**: heap bytes allocated per transmission (JMH's `-prof gc`).
      """;

  private MarkdownTables() {}

  /**
   * The whole report: the environment, the legend ({@link #LEGEND}), then every table.
   *
   * @param tables the tables
   * @param environment where and when, or {@code null} if unknown
   * @return Markdown
   */
  public static String render(List<ResultTable> tables, Environment environment) {
    StringBuilder md = new StringBuilder();
    if (environment != null) {
      md.append(String.format(Locale.ROOT,
          "Run %s on %d CPUs (%s), %s, %s; load average %.2f at start, %.2f at end.%n%n",
          environment.date(), environment.cpus(), environment.cpuModel(), environment.os(),
          environment.jdk(), environment.loadBefore(), environment.loadAfter()));
    }
    md.append(LEGEND).append('\n');
    for (ResultTable table : tables) {
      md.append(render(table)).append('\n');
    }
    return md.toString();
  }

  /**
   * One table: times, then allocations.
   *
   * @param table the table
   * @return Markdown
   */
  public static String render(ResultTable table) {
    StringBuilder md = new StringBuilder();
    md.append("### ").append(table.title()).append(", µs per transmission\n\n");
    header(md, table);
    for (ResultTable.Row row : table.rows()) {
      md.append("| ").append(row.label());
      for (ResultTable.Cell cell : row.cells()) {
        md.append(" | ").append(cell == null ? "—" : time(cell));
      }
      md.append(" |\n");
    }
    if (table.rows().stream()
        .flatMap(r -> r.cells().stream())
        .anyMatch(c -> c != null && !Double.isNaN(c.bytes()))) {
      md.append("\n").append(table.title()).append(", bytes allocated per transmission:\n\n");
      header(md, table);
      for (ResultTable.Row row : table.rows()) {
        md.append("| ").append(row.label());
        for (ResultTable.Cell cell : row.cells()) {
          md.append(" | ").append(cell == null || Double.isNaN(cell.bytes())
              ? "—" : String.format(Locale.ROOT, "%.1f", cell.bytes()));
        }
        md.append(" |\n");
      }
    }
    return md.toString();
  }

  private static void header(StringBuilder md, ResultTable table) {
    md.append("| |");
    for (String column : table.columns()) {
      md.append(' ').append(ResultTable.columnLabel(column)).append(" |");
    }
    md.append("\n|---|");
    md.append("---|".repeat(table.columns().size()));
    md.append('\n');
  }

  /**
   * A cell's text: {@code 0.00153 ± 0.00021 (0.81×)}; the ratio is left out when unknown.
   *
   * @param cell the cell
   * @return the text
   */
  public static String time(ResultTable.Cell cell) {
    BigDecimal micros = significant(cell.micros());
    String text = micros.toPlainString();
    if (!Double.isNaN(cell.errorMicros())) {
      BigDecimal error =
          BigDecimal.valueOf(cell.errorMicros()).setScale(Math.max(0, micros.scale()),
              RoundingMode.HALF_UP);
      text += " ± " + error.toPlainString();
    }
    if (!Double.isNaN(cell.ratio())) {
      text += String.format(Locale.ROOT, cell.ratio() < 10 ? " (%.2f×)" : " (%.0f×)", cell.ratio());
    }
    return text;
  }

  /** Three significant digits, trailing zeros kept (0.500, 0.00150); whole numbers above 999. */
  private static BigDecimal significant(double value) {
    if (value == 0 || !Double.isFinite(value)) {
      return BigDecimal.ZERO;
    }
    int exponent = (int) Math.floor(Math.log10(Math.abs(value)));
    return BigDecimal.valueOf(value).setScale(Math.max(0, 2 - exponent), RoundingMode.HALF_UP);
  }
}
