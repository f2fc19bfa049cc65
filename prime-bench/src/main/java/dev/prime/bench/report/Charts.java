package dev.prime.bench.report;

import java.io.IOException;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import org.knowm.xchart.BitmapEncoder;
import org.knowm.xchart.BitmapEncoder.BitmapFormat;
import org.knowm.xchart.CategoryChart;
import org.knowm.xchart.CategoryChartBuilder;
import org.knowm.xchart.style.Styler.LegendPosition;

/**
 * Draws result tables as bar charts with XChart: one chart per table, a group of bars per payload
 * size, a bar per row, microseconds per transmission on a logarithmic axis (the rows span four
 * orders of magnitude). Needs no display: call with {@code -Djava.awt.headless=true} on servers.
 */
public final class Charts {
  private static final int WIDTH = 1000;
  private static final int HEIGHT = 560;

  private Charts() {}

  /**
   * The chart of one table. Rows without any measured cell are left out; a missing cell is drawn
   * as no bar.
   *
   * @param table the table
   * @return the chart
   */
  public static CategoryChart chart(ResultTable table) {
    CategoryChart chart =
        new CategoryChartBuilder()
            .width(WIDTH)
            .height(HEIGHT)
            .title(table.title() + ": µs per transmission (log scale)")
            .xAxisTitle("payload")
            .yAxisTitle("µs per transmission")
            .build();
    chart.getStyler().setYAxisLogarithmic(true);
    chart.getStyler().setLegendPosition(LegendPosition.OutsideE);
    chart.getStyler().setYAxisDecimalPattern("0.####");
    // bar charts start their axis at 0, which a log axis cannot show: bound it by decades
    double min = Double.POSITIVE_INFINITY;
    double max = 0;
    for (ResultTable.Row row : table.rows()) {
      for (ResultTable.Cell cell : row.cells()) {
        if (cell != null && cell.micros() > 0) {
          min = Math.min(min, cell.micros());
          max = Math.max(max, cell.micros());
        }
      }
    }
    if (max > 0) {
      chart.getStyler().setYAxisMin(Math.pow(10, Math.floor(Math.log10(min))));
      chart.getStyler().setYAxisMax(Math.pow(10, Math.ceil(Math.log10(max))));
    }
    List<String> categories = new ArrayList<>();
    for (String column : table.columns()) {
      categories.add(ResultTable.columnLabel(column));
    }
    for (ResultTable.Row row : table.rows()) {
      List<Double> values = new ArrayList<>();
      boolean any = false;
      for (ResultTable.Cell cell : row.cells()) {
        // a log axis cannot draw 0: a missing cell becomes no bar (null)
        values.add(cell == null ? null : cell.micros());
        any |= cell != null;
      }
      if (any) {
        chart.addSeries(row.label(), categories, values);
      }
    }
    return chart;
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
      BitmapEncoder.saveBitmap(chart(table), file.toString(), BitmapFormat.PNG);
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
