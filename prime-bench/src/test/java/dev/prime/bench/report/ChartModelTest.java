package dev.prime.bench.report;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.Arrays;
import java.util.List;
import org.junit.jupiter.api.Test;

/** The charts' geometry: axis choice, zero baseline, error bar extents and their clipping. */
class ChartModelTest {

  private static ResultTable.Cell cell(double micros, double error) {
    return new ResultTable.Cell(micros, error, Double.NaN, Double.NaN);
  }

  private static ResultTable table(ResultTable.Cell... firstColumnThenSecondRow) {
    return new ResultTable("Test table", List.of("100", "1024"),
        List.of(
            new ResultTable.Row("base", true,
                Arrays.asList(firstColumnThenSecondRow[0], firstColumnThenSecondRow[1])),
            new ResultTable.Row("other", false,
                Arrays.asList(firstColumnThenSecondRow[2], firstColumnThenSecondRow[3]))));
  }

  @Test
  void timesCloseTogetherAreBarsOnALinearAxisFromZero() {
    // the Optimus table's shape: 158 ± 42 µs against 191 ± 100 µs
    ChartModel chart = Charts.chart(
        table(cell(158, 42), cell(281, 55), cell(191, 100), cell(324, 145)));
    assertEquals(ChartModel.Scale.LINEAR, chart.scale());
    assertEquals(0.0, chart.axisMin(), 0);
    assertEquals(0.0, chart.ticks().get(0), 0);
    assertEquals(0.0, chart.position(0), 0); // a bar starts at the axis' bottom
    ChartModel.Mark mark = chart.series().get(1).marks().get(0);
    assertEquals(91, mark.low(), 1e-9);
    assertEquals(291, mark.high(), 1e-9);
    assertFalse(mark.lowClipped());
    // the axis covers the highest interval top (324 + 145 = 469) with a round grid line
    assertEquals(500, chart.axisMax(), 1e-9);
    assertEquals(List.of(0.0, 50.0, 100.0, 150.0, 200.0, 250.0, 300.0, 350.0, 400.0, 450.0,
        500.0), chart.ticks());
    assertEquals(0.5, chart.position(250), 1e-12);
    assertEquals("base (baseline)", chart.series().get(0).label());
  }

  @Test
  void anIntervalReachingBelowZeroIsClippedAtZeroAndFlagged() {
    ChartModel chart = Charts.chart(
        table(cell(100, 10), cell(100, 10), cell(120, 250), cell(110, 5)));
    assertEquals(ChartModel.Scale.LINEAR, chart.scale());
    ChartModel.Mark wide = chart.series().get(1).marks().get(0);
    assertTrue(wide.lowClipped());
    assertEquals(0.0, wide.low(), 0);
    assertEquals(370, wide.high(), 1e-9);
    assertTrue(chart.anyClipped());
    assertFalse(chart.series().get(1).marks().get(1).lowClipped());
  }

  @Test
  void timesSpanningMoreThanTwentyfoldArePointsOnALogAxisOfWholeDecades() {
    // exactly 20× apart: still linear; just over: log
    assertEquals(ChartModel.Scale.LINEAR,
        Charts.chart(table(cell(1, 0.1), cell(1, 0.1), cell(20, 1), cell(20, 1))).scale());
    ChartModel chart =
        Charts.chart(table(cell(0.002, 0.0005), cell(0.002, 0.0005), cell(0.0401, 0.004),
            cell(0.0402, 0.004)));
    assertEquals(ChartModel.Scale.LOG, chart.scale());
    assertEquals(0.001, chart.axisMin(), 1e-15);
    assertEquals(0.1, chart.axisMax(), 1e-15);
    assertEquals(List.of(0.001, 0.01, 0.1), chart.ticks());
    assertEquals(0.5, chart.position(0.01), 1e-12); // the middle decade is the middle
    ChartModel.Mark base = chart.series().get(0).marks().get(0);
    assertEquals(0.0015, base.low(), 1e-15);
    assertEquals(0.0025, base.high(), 1e-15);
    assertFalse(chart.anyClipped());
  }

  @Test
  void onALogAxisAnIntervalReachingBelowZeroIsClippedAtTheAxisNotStretchingIt() {
    // Prime sources in the monomorphic table: 0.838 ± 2.415 µs next to FOR at 0.0023 µs
    ChartModel chart = Charts.chart(
        table(cell(0.0023, 0.0012), cell(0.0020, 0.0011), cell(0.838, 2.415), cell(0.354, 0.04)));
    assertEquals(ChartModel.Scale.LOG, chart.scale());
    assertEquals(0.0001, chart.axisMin(), 1e-15); // the decade below FOR's 0.0009 bottom
    assertEquals(10, chart.axisMax(), 1e-12); // 0.838 + 2.415 = 3.253
    ChartModel.Mark wide = chart.series().get(1).marks().get(0);
    assertTrue(wide.lowClipped());
    assertEquals(chart.axisMin(), wide.low(), 0);
    assertEquals(3.253, wide.high(), 1e-12);
    assertEquals(0.0, chart.position(wide.low()), 0);
  }

  @Test
  void anIntervalNearlyDownToZeroStretchesTheLogAxisByOneDecadeAtMost() {
    ChartModel chart = Charts.chart(
        table(cell(0.002, 0.001999), cell(0.002, 0.0001), cell(1, 0.1), cell(1, 0.1)));
    assertEquals(ChartModel.Scale.LOG, chart.scale());
    assertEquals(0.0001, chart.axisMin(), 1e-15); // 0.002 / 10, not 0.000001
    ChartModel.Mark nearZero = chart.series().get(0).marks().get(0);
    assertTrue(nearZero.lowClipped());
    assertEquals(0.0001, nearZero.low(), 1e-15);
  }

  @Test
  void aTableWithNothingToDrawIsRejectedWithTheReason() {
    ResultTable empty = new ResultTable("Empty", List.of("100"),
        List.of(new ResultTable.Row("base", true, Arrays.asList((ResultTable.Cell) null))));
    IllegalArgumentException e =
        assertThrows(IllegalArgumentException.class, () -> Charts.chart(empty));
    assertTrue(e.getMessage().contains("no positive time"), e.getMessage());
  }
}
