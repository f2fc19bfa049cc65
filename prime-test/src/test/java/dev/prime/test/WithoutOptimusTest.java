package dev.prime.test;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import java.io.File;
import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Arrays;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A test project without prime-optimus: a JVM whose class path lacks it runs an all-media
 * {@link PrimeTest}; the Liberty and Radiant runs pass, the Optimus run fails saying which
 * dependency to add.
 */
class WithoutOptimusTest {

  /** The test the JVM without prime-optimus runs. */
  static class OnEveryMedia {
    @PrimeTest
    void runs(PrimeCore core) {
      core.start();
    }
  }

  @Test
  void theOptimusRunFailsNamingTheDependencyToAddWhileTheOtherMediaRun(@TempDir Path dir)
      throws IOException, InterruptedException {
    String[] entries = System.getProperty("java.class.path").split(File.pathSeparator);
    String withoutOptimus =
        Arrays.stream(entries)
            .filter(entry -> !Path.of(entry).toString().contains("prime-optimus"))
            .collect(Collectors.joining(File.pathSeparator));
    assertEquals(entries.length - 1, withoutOptimus.split(File.pathSeparator).length,
        "exactly one class path entry is prime-optimus: " + String.join("\n", entries));
    Path out = dir.resolve("out.txt");
    Process jvm =
        new ProcessBuilder(
                Path.of(System.getProperty("java.home"), "bin", "java").toString(),
                "-Xmx256m",
                "-cp",
                withoutOptimus,
                KitMain.class.getName(),
                OnEveryMedia.class.getName())
            .redirectErrorStream(true)
            .redirectOutput(out.toFile())
            .start();
    try {
      assertTrue(jvm.waitFor(60, TimeUnit.SECONDS), "the JVM did not finish in 60 s");
    } finally {
      jvm.destroyForcibly();
    }
    List<String> lines =
        Files.readAllLines(out, StandardCharsets.UTF_8).stream()
            .filter(line -> line.startsWith("RUN "))
            .toList();
    String all = Files.readString(out, StandardCharsets.UTF_8);

    assertEquals(0, jvm.exitValue(), all);
    assertEquals(3, lines.size(), all);
    assertEquals("RUN Liberty|SUCCESSFUL|", lines.get(0));
    assertEquals("RUN Radiant|SUCCESSFUL|", lines.get(1));
    assertEquals(
        "RUN Optimus|FAILED|@PrimeTest runs this test on Optimus, but dev.prime:prime-optimus is"
            + " not on the test class path (there is no class dev.prime.optimus.OptimusCore). Add"
            + " the test dependency dev.prime:prime-optimus (Maven: <scope>test</scope>; Gradle:"
            + " testImplementation), or leave Optimus out: @PrimeTest(media = {...}) without"
            + " OPTIMUS.",
        lines.get(2));
  }
}
