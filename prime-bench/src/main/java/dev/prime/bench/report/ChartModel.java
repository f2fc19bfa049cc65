package dev.prime.bench.report;

import java.math.BigDecimal;
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;

/**
 * What a result table's chart shows, before any pixel is drawn: the axis, and for every row a
 * mark per payload column with its error interval. {@link ChartPainter} draws it; tests check it.
 *
 * <p>The axis is chosen so the picture cannot mislead. When a table's times stay within
 * {@value #LOG_SPREAD}× of each other the axis is linear from zero and each time is a bar, so a
 * bar's length is the time. When they span more (a hand-written loop at 2 ns and a thread
 * hand-off at 100 ns in one table), the axis is logarithmic, where a bar's length would mean
 * nothing (the axis has no zero), so each time is a point. Every mark carries the JMH score error
 * (99.9 % confidence interval) as its error bar; an interval reaching below the axis (below zero,
 * or below the log axis' first decade) is clipped there and flagged.
 *
 * @param title the table's title
 * @param valueAxisTitle the value axis' title, with its unit
 * @param scale linear (bars from zero) or logarithmic (points)
 * @param axisMin the axis' lowest value: 0 on a linear axis, a power of ten on a log axis
 * @param axisMax the axis' highest value, at or above every interval's top
 * @param ticks the values to label and draw grid lines at, ascending, from axisMin to axisMax
 * @param groups the payload columns' labels ({@code 100 B}, {@code 1 KB}, ...)
 * @param series one per row with at least one measured cell, in the table's order
 */
public record ChartModel(
    String title,
    String valueAxisTitle,
    Scale scale,
    double axisMin,
    double axisMax,
    List<Double> ticks,
    List<String> groups,
    List<Series> series) {

  /** Beyond this ratio of the largest to the smallest time the axis is logarithmic. */
  public static final double LOG_SPREAD = 20;

  /** How the value axis maps times and how a time is drawn. */
  public enum Scale {
    /** Linear axis from zero; each time is a bar from zero. */
    LINEAR,
    /** Logarithmic axis; each time is a point (a bar would have no zero to start from). */
    LOG
  }

  /**
   * One row of the table.
   *
   * @param label the row's label, {@code (baseline)} appended for the table's baseline row
   * @param baseline whether this is the row the others are compared with
   * @param marks one per group; {@code null} where nothing was measured
   */
  public record Series(String label, boolean baseline, List<Mark> marks) {
    /** Copies the marks (which may hold nulls). */
    public Series {
      marks = Collections.unmodifiableList(new ArrayList<>(marks));
    }
  }

  /**
   * One measured time and its error bar, in µs, clipped to the axis.
   *
   * @param value the mean time
   * @param low the error bar's bottom: value − error, or the axis' minimum if that is lower
   * @param high the error bar's top: value + error
   * @param hasError whether JMH reported an error (not with a single iteration); without one the
   *     error bar is empty ({@code low == high == value})
   * @param lowClipped whether value − error lies below the axis (and {@code low} was raised to it)
   */
  public record Mark(double value, double low, double high, boolean hasError, boolean lowClipped) {}

  /** Copies the lists. */
  public ChartModel {
    ticks = List.copyOf(ticks);
    groups = List.copyOf(groups);
    series = List.copyOf(series);
  }

  /**
   * The chart of one table: rows without any measured cell are left out.
   *
   * @param table the table
   * @return the model
   * @throws IllegalArgumentException if the table has no positive time to draw
   */
  public static ChartModel of(ResultTable table) {
    double minValue = Double.POSITIVE_INFINITY;
    double maxValue = 0;
    double minLow = Double.POSITIVE_INFINITY;
    double maxHigh = 0;
    for (ResultTable.Row row : table.rows()) {
      for (ResultTable.Cell cell : row.cells()) {
        if (cell != null && cell.micros() > 0) {
          double error = errorOf(cell);
          minValue = Math.min(minValue, cell.micros());
          maxValue = Math.max(maxValue, cell.micros());
          if (cell.micros() - error > 0) {
            minLow = Math.min(minLow, cell.micros() - error);
          }
          maxHigh = Math.max(maxHigh, cell.micros() + error);
        }
      }
    }
    if (maxValue == 0) {
      throw new IllegalArgumentException(
          "table '" + table.title() + "' has no positive time to chart: check its JSON's scores");
    }
    Scale scale = maxValue / minValue > LOG_SPREAD ? Scale.LOG : Scale.LINEAR;
    double axisMin;
    double axisMax;
    List<Double> ticks;
    if (scale == Scale.LOG) {
      // the first decade below every interval's bottom, but at most one decade below the smallest
      // time: an interval reaching down to almost zero is clipped rather than stretching the axis
      double lowest = Math.max(Math.min(minLow, minValue), minValue / 10);
      axisMin = decade(Math.floor(Math.log10(lowest)));
      axisMax = decade(Math.ceil(Math.log10(maxHigh)));
      if (axisMax <= axisMin) {
        axisMax = axisMin * 10;
      }
      ticks = new ArrayList<>();
      for (double tick = axisMin; tick <= axisMax * 1.000001; tick = decade(Math.log10(tick) + 1)) {
        ticks.add(tick);
      }
    } else {
      axisMin = 0;
      double step = linearStep(maxHigh);
      axisMax = Math.ceil(maxHigh / step) * step;
      ticks = new ArrayList<>();
      long count = Math.round(axisMax / step);
      for (long i = 0; i <= count; i++) {
        ticks.add(BigDecimal.valueOf(step).multiply(BigDecimal.valueOf(i)).doubleValue());
      }
    }
    List<String> groups = table.columns().stream().map(ResultTable::columnLabel).toList();
    List<Series> series = new ArrayList<>();
    for (ResultTable.Row row : table.rows()) {
      List<Mark> marks = new ArrayList<>();
      boolean any = false;
      for (ResultTable.Cell cell : row.cells()) {
        if (cell == null || cell.micros() <= 0) {
          marks.add(null);
          continue;
        }
        any = true;
        double error = errorOf(cell);
        double low = cell.micros() - error;
        boolean clipped = low < axisMin;
        marks.add(new Mark(cell.micros(), clipped ? axisMin : low, cell.micros() + error,
            !Double.isNaN(cell.errorMicros()), clipped));
      }
      if (any) {
        series.add(new Series(row.baseline() ? row.label() + " (baseline)" : row.label(),
            row.baseline(), marks));
      }
    }
    String axisTitle = scale == Scale.LOG
        ? "µs per transmission (log scale: each grid line is 10×)"
        : "µs per transmission";
    return new ChartModel(table.title(), axisTitle, scale, axisMin, axisMax, ticks, groups, series);
  }

  /**
   * Where a value lies along the value axis.
   *
   * @param value a time in µs (clamped to the axis)
   * @return 0 at the axis' minimum, 1 at its maximum, linear or logarithmic as the scale
   */
  public double position(double value) {
    double clamped = Math.min(axisMax, Math.max(axisMin, value));
    return scale == Scale.LOG
        ? Math.log(clamped / axisMin) / Math.log(axisMax / axisMin)
        : (clamped - axisMin) / (axisMax - axisMin);
  }

  /**
   * Whether any mark's interval was clipped at the bottom of the axis.
   *
   * @return true if a legend line must explain the clipped error bars
   */
  public boolean anyClipped() {
    return series.stream().flatMap(s -> s.marks().stream())
        .anyMatch(m -> m != null && m.lowClipped());
  }

  /**
   * Whether any mark has no error (a single iteration).
   *
   * @return true if a legend line must say that some marks have no error bar
   */
  public boolean anyWithoutError() {
    return series.stream().flatMap(s -> s.marks().stream())
        .anyMatch(m -> m != null && !m.hasError());
  }

  private static double errorOf(ResultTable.Cell cell) {
    return Double.isNaN(cell.errorMicros()) ? 0 : Math.abs(cell.errorMicros());
  }

  /** 10 to the power of a whole exponent, exactly as written in decimal (0.001, not 0.0010000001). */
  private static double decade(double exponent) {
    return BigDecimal.ONE.scaleByPowerOfTen((int) Math.round(exponent)).doubleValue();
  }

  /** A 1, 2 or 5 step (times a power of ten) giving 4 to 10 grid lines up to max. */
  private static double linearStep(double max) {
    double magnitude = decade(Math.floor(Math.log10(max)));
    for (double factor : new double[] {0.1, 0.2, 0.5, 1, 2, 5}) {
      double step = BigDecimal.valueOf(magnitude).multiply(BigDecimal.valueOf(factor)).doubleValue();
      if (max / step <= 10) {
        return step;
      }
    }
    return magnitude * 10;
  }
}
