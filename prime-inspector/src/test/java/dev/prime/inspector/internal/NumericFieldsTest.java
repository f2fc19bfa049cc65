package dev.prime.inspector.internal;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.util.List;
import java.util.Map;
import org.junit.jupiter.api.Test;

class NumericFieldsTest {
  record Pose(double x, double y, double heading) {}

  record Estimate(long step, Pose pose, String note, boolean moving, List<Double> history) {}

  record Deep(Deep inner, int level) {}

  @Test
  void numbersBooleansAndRecordComponentsByPath() {
    NumericFields fields = new NumericFields();
    assertEquals(Map.of("value", 2.5), fields.of(2.5));
    assertEquals(Map.of("value", 7.0), fields.of(7L));
    assertEquals(Map.of("value", 1.0), fields.of(true));
    assertEquals(Map.of(), fields.of("text"));
    assertEquals(Map.of(), fields.of(List.of(1, 2)));
    Map<String, Double> estimate =
        fields.of(new Estimate(3, new Pose(1, 2, 0.5), "n", false, List.of(1.0)));
    assertEquals(List.of("step", "pose.x", "pose.y", "pose.heading", "moving"),
        List.copyOf(estimate.keySet()));
    assertEquals(List.of(3.0, 1.0, 2.0, 0.5, 0.0), List.copyOf(estimate.values()));
  }

  @Test
  void nestingAndFieldCountAreBounded() {
    NumericFields fields = new NumericFields();
    Deep deep = new Deep(new Deep(new Deep(new Deep(null, 4), 3), 2), 1);
    assertEquals(Map.of("level", 1.0, "inner.level", 2.0, "inner.inner.level", 3.0), fields.of(deep));
    record Wide(int a, int b, int c, int d, int e, int f, int g, int h, int i, int j, int k, int l,
        int m, int n) {}
    assertEquals(NumericFields.MAX_FIELDS,
        fields.of(new Wide(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14)).size());
  }
}
