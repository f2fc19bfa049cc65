package dev.prime.bench;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.ValueSource;

class SpeedPairingProbeTest {

  @Test
  void countsEachPairingOfSpeeds() {
    List<double[]> pairs =
        List.of(
            new double[] {116, 306},
            new double[] {120, 290},
            new double[] {478, 1355},
            new double[] {450, 310},
            new double[] {110, 1200});
    assertEquals(
        "5 windows; round trip fast (<= 280 ns): row fast 2, row slow (> 700 ns) 1;"
            + " round trip slow: row fast 1, row slow 1",
        SpeedPairingProbe.summary(pairs, "row", SpeedPairingProbe.SLOW_ROW_NANOS));
  }

  @ParameterizedTest
  @ValueSource(strings = {"row", "handoff"})
  void measuresBothInWindowsOfOneJvm(String row) throws InterruptedException {
    PrintStream out = System.out;
    ByteArrayOutputStream printed = new ByteArrayOutputStream();
    System.setOut(new PrintStream(printed, true, StandardCharsets.UTF_8));
    try {
      SpeedPairingProbe.main(new String[] {"100", "3", "1", "0", row});
    } finally {
      System.setOut(out);
    }
    String text = printed.toString(StandardCharsets.UTF_8);
    String window = "window \\d: round trip \\d+ ns, " + row + " \\d+ ns";
    assertEquals(3, text.lines().filter(line -> line.matches(window)).count(), text);
    assertTrue(text.contains("3 windows; round trip fast (<= 280 ns): " + row + " fast"), text);
  }

  @Test
  void refusesAWindowShorterThanAMillisecondANonNumberOrAnUnknownRow() {
    IllegalArgumentException e =
        assertThrows(IllegalArgumentException.class, () -> SpeedPairingProbe.main(new String[] {"100", "3", "0"}));
    assertTrue(
        e.getMessage().contains("argument 3 is '0'") && e.getMessage().contains("windowMillis (1 to 60000)"),
        e.getMessage());
    e = assertThrows(IllegalArgumentException.class, () -> SpeedPairingProbe.main(new String[] {"100", "ten"}));
    assertTrue(e.getMessage().contains("argument 2 is 'ten'"), e.getMessage());
    e = assertThrows(IllegalArgumentException.class, () -> SpeedPairingProbe.main(new String[] {"100", "3", "1", "0", "sync"}));
    assertTrue(e.getMessage().contains("row or handoff"), e.getMessage());
  }
}
