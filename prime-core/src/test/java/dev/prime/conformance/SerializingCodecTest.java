package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Repeat;
import dev.prime.Tick;
import dev.prime.Tuple2;
import dev.prime.Tuple3;
import dev.prime.Tuple4;
import dev.prime.Tuple5;
import java.time.Instant;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

/** The kit's copy codec copies the core's value types, which are not {@code Serializable}. */
class SerializingCodecTest {

  private static Object copy(Object value) {
    return SerializingCodec.INSTANCE.decode(SerializingCodec.INSTANCE.encode(value));
  }

  @Test
  void copiesTheCoresValueTypesAlsoInsideOtherValues() {
    Instant due = Instant.parse("2026-01-02T03:04:05.123456789Z");
    List<Object> values =
        List.of(
            new Tick(3, due),
            new Tuple2<>(1, "a"),
            new Tuple3<>(1, 2.5, List.of(3)),
            new Tuple4<>('x', null, 4L, "d"),
            new Tuple5<>(1, 2, 3, 4, new Tuple2<>(new Tick(1, due), 5)),
            Repeat.again(List.of(1, 2)),
            Repeat.stop("done"),
            List.of(new Tuple2<>(1, 2), new Tick(2, due)));
    for (Object value : values) {
      Object copied = copy(value);
      assertEquals(value, copied, "the copy of " + value);
      assertNotSame(value, copied, "a copy, not the value itself");
    }
  }

  @Test
  void aTupleCopiesItsMutableComponents() {
    List<Integer> inside = new ArrayList<>(List.of(1));
    @SuppressWarnings("unchecked")
    Tuple2<List<Integer>, Integer> copied = (Tuple2<List<Integer>, Integer>) copy(new Tuple2<>(inside, 2));
    inside.add(2);
    assertEquals(List.of(1), copied.first(), "the component was copied");
  }

  @Test
  void refusesATypeItDoesNotKnowAlsoInsideATuple() {
    Object unknown = new Object();
    IllegalArgumentException alone =
        assertThrows(IllegalArgumentException.class, () -> SerializingCodec.INSTANCE.encode(unknown));
    assertTrue(alone.getMessage().contains("java.lang.Object"), alone.getMessage());
    assertThrows(
        IllegalArgumentException.class,
        () -> SerializingCodec.INSTANCE.encode(new Tuple2<>(1, unknown)));
  }
}
