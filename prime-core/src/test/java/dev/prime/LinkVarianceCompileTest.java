package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.File;
import java.io.IOException;
import java.net.URISyntaxException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * Linking is as variant as {@link java.util.function.Function#andThen}, and no more: the sound
 * links compile, the unsound ones (a next block that cannot take what comes out, a result typed
 * wider than it is) do not. Compiles snippets with the JDK's {@code javac} against prime-core's
 * classes, in one run; the conformance kit's {@code LinkVarianceConformance} runs the sound links on
 * every media.
 */
class LinkVarianceCompileTest {

  private static final String IMPORTS = "import dev.prime.*;\n";

  /** Each compiles only if linking is variant. */
  private static final String SOUND =
      IMPORTS
          + "class Sound {\n"
          + "  void links(PrimeCore core, Chain<Integer, Integer> inc, Block<Object, String> describe,\n"
          + "      Chain<Object, String> describeChain, Source<Integer> numbers,\n"
          + "      Block<Number, Integer> floor) {\n"
          + "    Chain<Integer, String> a = inc.then(describe);\n"
          + "    Chain<Integer, String> b = inc.then(describeChain);\n"
          + "    Chain<Integer, Number> c = inc.then(floor);\n"
          + "    Chain<Integer, String> d = core.link(inc, describeChain);\n"
          + "    Source<String> e = numbers.then(describe);\n"
          + "    Source<String> f = numbers.then(describeChain);\n"
          + "    Source<Number> g = numbers.then(floor);\n"
          + "    Source<String> h = core.link(numbers, describeChain);\n"
          + "    Block<Integer, CharSequence> i = Block.narrow(describe);\n"
          + "    Chain<Integer, CharSequence> j = core.ifThenElse(x -> x > 0, describeChain, inc.then(describe));\n"
          + "    Chain<java.util.List<Integer>, java.util.List<Number>> k = core.forEach(inc.then(floor));\n"
          + "    Chain<Integer, Tuple2<String, Integer>> l = core.union(describeChain, inc);\n"
          + "    Chain<Integer, Number> m = core.guard(x -> x > 0, inc.then(floor), x -> 0L);\n"
          + "  }\n"
          + "}\n";

  /** Each must be refused: the types do not fit. */
  private static final Map<String, String> UNSOUND = new LinkedHashMap<>();

  static {
    UNSOUND.put(
        "NextTakesLess",
        "void f(Chain<Integer, Object> anything, Block<Integer, String> onlyIntegers) {"
            + " anything.then(onlyIntegers); }");
    UNSOUND.put(
        "NextChainTakesLess",
        "void f(Chain<Integer, Object> anything, Chain<Integer, String> onlyIntegers) {"
            + " anything.then(onlyIntegers); }");
    UNSOUND.put(
        "ResultWiderThanTyped",
        "void f(Chain<Integer, Integer> inc, Block<Object, Object> any) {"
            + " Chain<Integer, String> r = inc.then(any); }");
    UNSOUND.put(
        "SourceOfMoreThanTheChainTakes",
        "void f(Source<Object> anything, Chain<Integer, String> onlyIntegers) {"
            + " anything.then(onlyIntegers); }");
    UNSOUND.put(
        "CoreLinkOfMismatchedChains",
        "void f(PrimeCore core, Chain<Integer, Number> numbers, Chain<Integer, String> ints) {"
            + " core.link(numbers, ints); }");
    UNSOUND.put(
        "BranchTakesLess",
        "void f(PrimeCore core, Chain<Number, String> numbers, Chain<Integer, String> ints) {"
            + " Chain<Number, String> r = core.ifThenElse(x -> true, numbers, ints); }");
    UNSOUND.put(
        "UnionOutputWiderThanTyped",
        "void f(PrimeCore core, Chain<Integer, Object> any, Chain<Integer, Integer> ints) {"
            + " Chain<Integer, Tuple2<String, Integer>> r = core.union(any, ints); }");
    UNSOUND.put(
        "NarrowToAWiderInput",
        "void f(Block<Integer, String> onlyIntegers) {"
            + " Block<Object, String> b = Block.narrow(onlyIntegers); }");
  }

  @Test
  void soundLinksCompileAndUnsoundOnesDoNot(@TempDir Path dir)
      throws IOException, InterruptedException, URISyntaxException {
    List<String> files = new ArrayList<>();
    files.add(write(dir, "Sound", SOUND).toString());
    for (Map.Entry<String, String> unsound : UNSOUND.entrySet()) {
      String source = IMPORTS + "class " + unsound.getKey() + " {\n  " + unsound.getValue() + "\n}\n";
      files.add(write(dir, unsound.getKey(), source).toString());
    }
    String output = javac(dir, files);
    for (String name : UNSOUND.keySet()) {
      assertTrue(
          output.contains(name + ".java:3: error:"),
          name + " must not compile; javac said:\n" + output);
    }
    assertTrue(!output.contains("Sound.java"), "the sound links compile; javac said:\n" + output);
    assertEquals(
        UNSOUND.size(),
        output.lines().filter(l -> l.contains(".java:") && l.contains(": error:")).count(),
        "one error per unsound snippet; javac said:\n" + output);
  }

  private static Path write(Path dir, String name, String source) throws IOException {
    return Files.writeString(dir.resolve(name + ".java"), source, StandardCharsets.UTF_8);
  }

  /** Runs the JDK's javac on {@code files}; returns what it printed. */
  private static String javac(Path dir, List<String> files)
      throws IOException, InterruptedException, URISyntaxException {
    Path javac = Path.of(System.getProperty("java.home"), "bin", "javac");
    assertTrue(Files.isExecutable(javac), "the tests run on a JDK with javac: " + javac);
    String classpath =
        Path.of(PrimeCore.class.getProtectionDomain().getCodeSource().getLocation().toURI())
            + File.pathSeparator
            + Path.of(
                org.slf4j.Logger.class.getProtectionDomain().getCodeSource().getLocation().toURI());
    List<String> command = new ArrayList<>();
    command.add(javac.toString());
    command.addAll(
        List.of("-J-Xshare:auto", "-J-XX:TieredStopAtLevel=1", "-Xmaxerrs", "100", "-proc:none"));
    command.addAll(List.of("-d", dir.resolve("out").toString(), "-cp", classpath));
    command.addAll(files);
    Process process = new ProcessBuilder(command).redirectErrorStream(true).start();
    byte[] printed = process.getInputStream().readAllBytes();
    assertTrue(process.waitFor(60, TimeUnit.SECONDS), "javac finished within 60 s");
    return new String(printed, StandardCharsets.UTF_8);
  }
}
