package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

/** The pairing rules of the combinators, value by value, without threads. */
class PairingTest {

  private static List<Object> feed(Pairing pairing, Object[][] inputs) {
    List<Object> out = new ArrayList<>();
    for (Object[] step : inputs) {
      pairing.accept((Integer) step[0], step[1], out::add);
    }
    return out;
  }

  @Test
  void zipKeepsAtMostTheLimitOfUnpairedValuesPerInputDroppingTheOldest() {
    List<Integer> dropped = new ArrayList<>();
    Pairing zip = Pairing.zip(2, 4, v -> new Tuple2<>(v[0], v[1]), dropped::add);
    List<Object> out = new ArrayList<>();
    for (int i = 1; i <= 10; i++) {
      zip.accept(0, i, out::add);
    }
    assertEquals(List.of(), out);
    assertEquals(List.of(0, 0, 0, 0, 0, 0), dropped, "a1..a6 dropped, one at a time");
    for (String b : List.of("w", "x", "y", "z", "late")) {
      zip.accept(1, b, out::add);
    }
    assertEquals(
        List.of(new Tuple2<>(7, "w"), new Tuple2<>(8, "x"), new Tuple2<>(9, "y"), new Tuple2<>(10, "z")),
        out);
    zip.accept(0, 11, out::add);
    assertEquals(new Tuple2<>(11, "late"), out.get(out.size() - 1));
  }

  @Test
  void combineLatestUpdatesTheLatestUntilEveryInputHasOneThenEmitsOnEveryValue() {
    Pairing latest = Pairing.combineLatest(2, v -> new Tuple2<>(v[0], v[1]));
    List<Object> out =
        feed(latest, new Object[][] {{0, 1}, {0, 2}, {0, 3}, {1, "x"}, {1, "y"}, {0, 4}});
    assertEquals(
        List.of(new Tuple2<>(3, "x"), new Tuple2<>(3, "y"), new Tuple2<>(4, "y")), out);
  }

  @Test
  void withLatestFromDropsValuesBeforeTheOtherHasOneAndNeverEmitsOnTheOther() {
    List<Object> out =
        feed(
            Pairing.withLatestFrom(),
            new Object[][] {{0, 1}, {0, 2}, {1, "x"}, {1, "y"}, {0, 3}, {1, "z"}, {0, 4}});
    assertEquals(List.of(new Tuple2<>(3, "y"), new Tuple2<>(4, "z")), out);
  }

  @Test
  void mergeEmitsEveryValueAsItComes() {
    assertEquals(
        List.of(1, "a", 2), feed(Pairing.merge(), new Object[][] {{0, 1}, {1, "a"}, {0, 2}}));
  }
}
