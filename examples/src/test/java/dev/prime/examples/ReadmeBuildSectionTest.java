package dev.prime.examples;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.Set;
import java.util.TreeSet;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.Test;

/**
 * The README's "Using Prime in your build" names what is published as it is: every artifact the
 * BOM manages, and the module name of each one that is not a JPMS module.
 */
class ReadmeBuildSectionTest {
  private static final Pattern ARTIFACT = Pattern.compile("<artifactId>([^<]+)</artifactId>");
  private static final Pattern TICKED = Pattern.compile("`([^`]+)`");

  private static String section() throws IOException {
    String readme = Files.readString(Path.of("../README.md"));
    int start = readme.indexOf("## Using Prime in your build");
    return readme.substring(start, readme.indexOf("\n## ", start + 1));
  }

  /** The artifacts prime-bom manages, itself included (the README's table lists it too). */
  private static Set<String> bomArtifacts() throws IOException {
    String bom = Files.readString(Path.of("../prime-bom/pom.xml"));
    Set<String> artifacts = new TreeSet<>();
    Matcher m = ARTIFACT.matcher(bom);
    while (m.find()) {
      artifacts.add(m.group(1));
    }
    return artifacts;
  }

  @Test
  void theTableOfArtifactsListsEveryArtifactOfTheBom() throws IOException {
    Set<String> listed = new TreeSet<>();
    for (String line : section().lines().toList()) {
      if (line.startsWith("| `")) {
        Matcher m = TICKED.matcher(line.substring(0, line.indexOf('|', 1)));
        while (m.find()) {
          listed.add(m.group(1));
        }
      }
    }
    assertEquals(bomArtifacts(), listed, "the README's table of artifacts and prime-bom's list");
  }

  @Test
  void everyArtifactThatIsNoJpmsModuleHasItsAutomaticModuleNameInTheReadme() throws IOException {
    String text = section().replaceAll("\\s+", " ");
    List<String> missing = new ArrayList<>();
    for (String artifact : bomArtifacts()) {
      Path pom = Path.of("..", artifact, "pom.xml");
      if (artifact.equals("prime-bom")
          || Files.exists(Path.of("..", artifact, "src/main/java/module-info.java"))) {
        continue;
      }
      Matcher m = Pattern.compile("<Automatic-Module-Name>([^<]+)</Automatic-Module-Name>")
          .matcher(Files.readString(pom));
      assertTrue(m.find(), artifact + " has an Automatic-Module-Name");
      if (!text.contains("`" + m.group(1) + "`")) {
        missing.add(artifact + " (" + m.group(1) + ")");
      }
    }
    assertEquals(List.of(), missing, "artifacts whose module name the README does not give");
  }
}
