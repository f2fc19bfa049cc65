package dev.prime.examples;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.ByteArrayOutputStream;
import java.io.IOException;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import org.junit.jupiter.api.Test;

class QuickStartTest {

  @Test
  void printsTheConvertedReadings() throws InterruptedException {
    ByteArrayOutputStream out = new ByteArrayOutputStream();

    QuickStart.run(new PrintStream(out, true, StandardCharsets.UTF_8));

    assertEquals(List.of("71 F", "212.0"), out.toString(StandardCharsets.UTF_8).lines().toList());
  }

  /** The README shows the code between the quick-start markers of QuickStart.java, verbatim. */
  @Test
  void readmeShowsTheCompiledQuickStart() throws IOException {
    String source =
        Files.readString(Path.of("src/main/java/dev/prime/examples/QuickStart.java"));
    String readme = Files.readString(Path.of("../README.md"));
    String begin = "// quick-start:begin\n";
    String end = "    // quick-start:end";
    String body =
        source.substring(source.indexOf(begin) + begin.length(), source.indexOf(end));
    String snippet = body.lines().map(line -> line.length() >= 4 ? line.substring(4) : line)
        .reduce("", (a, b) -> a + b + "\n");

    assertTrue(
        readme.contains(snippet),
        "README.md must contain the quick start of QuickStart.java, unindented by 4:\n" + snippet);
  }
}
