package dev.prime.examples;

import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import org.junit.jupiter.api.Test;

class ReadmeTestingSectionTest {

  /** The README's testing section shows ThermometerTest between its markers, verbatim. */
  @Test
  void readmeShowsTheCompiledThermometerTest() throws IOException {
    String source =
        Files.readString(Path.of("src/test/java/dev/prime/examples/ThermometerTest.java"));
    String readme = Files.readString(Path.of("../README.md"));
    String begin = "// testing:begin\n";
    String snippet =
        source.substring(source.indexOf(begin) + begin.length(), source.indexOf("// testing:end"));

    assertTrue(
        readme.contains("```java\n" + snippet + "```\n"),
        "README.md must show the test of ThermometerTest.java between its markers:\n" + snippet);
  }
}
