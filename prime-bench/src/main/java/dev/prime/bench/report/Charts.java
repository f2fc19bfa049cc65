package dev.prime.bench.report;

import java.io.IOException;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;

/**
 * One PNG chart per result table: payload columns along the bottom, a mark per row with the JMH
 * error bar (99.9 % confidence interval). A table whose times stay within
 * {@value ChartModel#LOG_SPREAD}× of each other gets bars on a linear axis from zero; a wider one
 * gets points on a log axis (see {@link ChartModel}). Drawn with Java2D: call with
 * {@code -Djava.awt.headless=true} on servers.
 */
public final class Charts {
  private Charts() {}

  /**
   * The chart of one table, as a model (what {@link #writePng} draws).
   *
   * @param table the table
   * @return the chart's model
   */
  public static ChartModel chart(ResultTable table) {
    return ChartModel.of(table);
  }

  /**
   * Writes every table's chart as a PNG file in {@code directory}.
   *
   * @param tables the tables
   * @param directory where to write (must exist)
   * @return the files written, in table order
   * @throws IOException if a file cannot be written
   */
  public static List<Path> writePng(List<ResultTable> tables, Path directory) throws IOException {
    List<Path> files = new ArrayList<>();
    for (ResultTable table : tables) {
      Path file = directory.resolve(fileName(table) + ".png");
      ChartPainter.writePng(chart(table), file);
      files.add(file);
    }
    return files;
  }

  /**
   * The chart's file name without extension, from the table's title.
   *
   * @param table the table
   * @return e.g. {@code synchronous-mode-polluted}
   */
  public static String fileName(ResultTable table) {
    return table.title().toLowerCase(Locale.ROOT).replaceAll("[^a-z0-9]+", "-")
        .replaceAll("^-|-$", "");
  }
}
