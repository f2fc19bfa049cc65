package dev.prime.bench;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;
import org.junit.jupiter.api.Test;

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
        SpeedPairingProbe.summary(pairs));
  }

  @Test
  void measuresBothInWindowsOfOneJvm() throws InterruptedException {
    PrintStream out = System.out;
    ByteArrayOutputStream printed = new ByteArrayOutputStream();
    System.setOut(new PrintStream(printed, true, StandardCharsets.UTF_8));
    try {
      SpeedPairingProbe.main(new String[] {"100", "3", "1", "0"});
    } finally {
      System.setOut(out);
    }
    String text = printed.toString(StandardCharsets.UTF_8);
    assertEquals(3, text.lines().filter(line -> line.matches("window \\d: round trip \\d+ ns, row \\d+ ns")).count(), text);
    assertTrue(text.contains("3 windows; round trip fast"), text);
  }

  @Test
  void refusesAWindowShorterThanAMillisecond() {
    IllegalArgumentException e =
        assertThrows(IllegalArgumentException.class, () -> SpeedPairingProbe.main(new String[] {"100", "3", "0"}));
    assertTrue(e.getMessage().contains("windowMillis >= 1"), e.getMessage());
  }
}
