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
  private MarkdownTables() {}

  /**
   * The whole report: the environment, then every table.
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
