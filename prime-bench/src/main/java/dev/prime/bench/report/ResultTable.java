package dev.prime.bench.report;

import java.util.ArrayList;
import java.util.Collections;
import java.util.Comparator;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.TreeSet;

/**
 * One table of results, laid out like the paper's Table 1: a row per family, a column per
 * payload size, each cell a time per transmission with its error, its ratio to the table's
 * baseline row (FOR) and its allocation.
 *
 * @param title e.g. {@code Synchronous mode (polluted)}
 * @param columns payload sizes in bytes, ascending (or {@code -} when the family has none)
 * @param rows the rows, in the families' order
 */
public record ResultTable(String title, List<String> columns, List<Row> rows) {

  /** A missing payload parameter. */
  public static final String NO_PAYLOAD = "-";

  /** Copies the lists. */
  public ResultTable {
    columns = List.copyOf(columns);
    rows = List.copyOf(rows);
  }

  /**
   * One row.
   *
   * @param label the family's row label
   * @param baseline whether this is the row the others are compared with
   * @param cells one per column; {@code null} where nothing was measured
   */
  public record Row(String label, boolean baseline, List<Cell> cells) {
    /** Copies the cells (which may hold nulls). */
    public Row {
      cells = Collections.unmodifiableList(new ArrayList<>(cells));
    }
  }

  /**
   * One measured cell.
   *
   * @param micros mean time per transmission, microseconds
   * @param errorMicros its error, microseconds ({@code NaN} if unknown)
   * @param ratio micros divided by the baseline row's in the same column ({@code NaN} if none)
   * @param bytes allocation per transmission ({@code NaN} if not profiled)
   */
  public record Cell(double micros, double errorMicros, double ratio, double bytes) {}

  /**
   * Builds the tables of a suite from its measurements: one per (table title, scenario), in the
   * families' order. Measurements of no family are ignored.
   *
   * @param families the suite
   * @param measurements the results
   * @return the tables that have at least one measured cell
   */
  public static List<ResultTable> build(List<Family> families, List<Measurement> measurements) {
    Map<String, List<String>> scenariosByTable = new LinkedHashMap<>();
    for (Family family : families) {
      List<String> scenarios =
          scenariosByTable.computeIfAbsent(family.table(), t -> new ArrayList<>());
      for (String scenario : family.scenarios()) {
        if (!scenarios.contains(scenario)) {
          scenarios.add(scenario);
        }
      }
    }
    List<ResultTable> tables = new ArrayList<>();
    scenariosByTable.forEach(
        (table, scenarios) -> {
          for (String scenario : scenarios) {
            String title = scenarios.size() > 1 ? table + " (" + scenario + ")" : table;
            List<Family> members =
                families.stream()
                    .filter(f -> f.table().equals(table) && f.scenarios().contains(scenario))
                    .toList();
            ResultTable built = build(title, scenario, members, measurements);
            if (built.rows().stream().anyMatch(r -> r.cells().stream().anyMatch(Objects::nonNull))) {
              tables.add(built);
            }
          }
        });
    return tables;
  }

  private static ResultTable build(
      String title, String scenario, List<Family> members, List<Measurement> measurements) {
    Map<Family, Map<String, Measurement>> byFamily = new LinkedHashMap<>();
    TreeSet<String> columns = new TreeSet<>(Comparator.comparingLong(ResultTable::payloadOrder));
    for (Family family : members) {
      Map<String, Measurement> byPayload = new LinkedHashMap<>();
      for (Measurement m : measurements) {
        if (m.benchmark().equals(family.benchmarkName())
            && m.param("scenario", scenario).equals(scenario)) {
          String payload = m.param("payload", NO_PAYLOAD);
          byPayload.put(payload, m);
          columns.add(payload);
        }
      }
      byFamily.put(family, byPayload);
    }
    Map<String, Measurement> baseline =
        members.stream().filter(Family::baseline).findFirst().map(byFamily::get).orElse(Map.of());
    List<Row> rows = new ArrayList<>();
    for (Family family : members) {
      List<Cell> cells = new ArrayList<>();
      for (String column : columns) {
        Measurement m = byFamily.get(family).get(column);
        if (m == null) {
          cells.add(null);
          continue;
        }
        Measurement base = baseline.get(column);
        double ratio = base == null ? Double.NaN : m.micros() / base.micros();
        cells.add(new Cell(m.micros(), m.errorMicros(), ratio, m.bytes()));
      }
      rows.add(new Row(family.row(), family.baseline(), cells));
    }
    return new ResultTable(title, new ArrayList<>(columns), rows);
  }

  private static long payloadOrder(String payload) {
    try {
      return Long.parseLong(payload);
    } catch (NumberFormatException notANumber) {
      return Long.MAX_VALUE;
    }
  }

  /**
   * A column's label: the payload's size in B or KB.
   *
   * @param column a payload size in bytes, or {@link #NO_PAYLOAD}
   * @return e.g. {@code 100 B}, {@code 1 KB}, {@code 10 KB}
   */
  public static String columnLabel(String column) {
    long bytes = payloadOrder(column);
    if (bytes == Long.MAX_VALUE) {
      return column;
    }
    return bytes >= 1024 && bytes % 1024 == 0 ? bytes / 1024 + " KB" : bytes + " B";
  }
}
