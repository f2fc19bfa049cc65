package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.SortedSet;
import java.util.TreeSet;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.Test;

/** The README's table "What is checked" names every stress test of the suite, and nothing else. */
class JcstressReadmeTest {
  private static final Pattern ROW = Pattern.compile("^\\| `([A-Za-z.]+)`");

  @Test
  void theReadmesTableNamesEveryTestOfTheSuite() throws IOException {
    // the tests' working directory is target (see the pom)
    String readme = Files.readString(Path.of("..", "README.md"));
    String table = readme.substring(readme.indexOf("## What is checked"), readme.indexOf("The four `NoSpin`"));
    SortedSet<String> listed = new TreeSet<>();
    for (String line : table.lines().toList()) {
      Matcher row = ROW.matcher(line);
      if (row.find()) {
        listed.add("dev.prime." + row.group(1));
      }
    }
    SortedSet<String> suite = new TreeSet<>();
    for (String test : JcstressRun.tests(JcstressRunTest.SUITE)) {
      suite.add(test.replace('$', '.'));
    }
    assertEquals(suite, listed, "the tests jcstress runs and those the README's table lists");
  }
}
