package dev.prime.examples;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import dev.prime.radiant.RadiantCore;
import java.io.ByteArrayOutputStream;
import java.io.File;
import java.net.URISyntaxException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.stream.Collectors;
import javax.tools.JavaCompiler;
import javax.tools.ToolProvider;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A JPMS application runs Prime from the module path with no {@code --add-modules}: an
 * application module that requires only {@code dev.prime.liberty} and {@code dev.prime.radiant}
 * is compiled, then run in a real JVM ({@code java --module-path ... -m ...}) whose module path
 * holds the Prime jars, ByteBuddy and SLF4J (API and a provider). SLF4J's module is resolved
 * because {@code dev.prime} requires it; the provider is bound as a service, so SLF4J does not
 * fall back to its no-operation logger.
 */
class ModulePathTest {

  private static final String MODULE_INFO =
      "module prime.modulepath.app {\n"
          + "  requires dev.prime.liberty;\n"
          + "  requires dev.prime.radiant;\n"
          + "}\n";

  private static final String MAIN =
      "package app;\n"
          + "import dev.prime.Block;\n"
          + "import dev.prime.PrimeCore;\n"
          + "import dev.prime.liberty.LibertyCore;\n"
          + "import dev.prime.radiant.RadiantCore;\n"
          + "public final class Main {\n"
          + "  public static void main(String[] args) throws Exception {\n"
          + "    System.out.println(\"MODULES \" + Main.class.getModule().getName() + \" \"\n"
          + "        + PrimeCore.class.getModule().getName());\n"
          + "    for (PrimeCore core : new PrimeCore[] {new LibertyCore(), new RadiantCore()}) {\n"
          + "      try (core) {\n"
          + "        Block<Integer, Integer> twice = core.chain(\"inc\", (Integer x) -> x + 1)\n"
          + "            .then(core.chain(\"double\", (Integer x) -> x * 2)).toBlock();\n"
          + "        core.start();\n"
          + "        System.out.println(\"RESULT \" + core.getClass().getSimpleName() + \" \"\n"
          + "            + twice.process(20));\n"
          + "      }\n"
          + "    }\n"
          + "  }\n"
          + "}\n";

  @Test
  void anApplicationModuleRunsPrimeWithoutAddModules(@TempDir Path dir) throws Exception {
    Path src = dir.resolve("src");
    Files.createDirectories(src.resolve("app"));
    Files.writeString(src.resolve("module-info.java"), MODULE_INFO);
    Files.writeString(src.resolve("app/Main.java"), MAIN);
    Path classes = dir.resolve("classes");

    List<Path> primeModules = new ArrayList<>();
    primeModules.add(location(PrimeCore.class));
    primeModules.add(location(LibertyCore.class));
    primeModules.add(location(RadiantCore.class));
    primeModules.add(location(Class.forName("net.bytebuddy.ByteBuddy")));
    primeModules.add(location(Class.forName("org.slf4j.LoggerFactory")));
    String compilePath = joined(primeModules);

    JavaCompiler javac = ToolProvider.getSystemJavaCompiler();
    ByteArrayOutputStream javacOutput = new ByteArrayOutputStream();
    int compiled =
        javac.run(
            null,
            javacOutput,
            javacOutput,
            "--module-path", compilePath,
            "-d", classes.toString(),
            src.resolve("module-info.java").toString(),
            src.resolve("app/Main.java").toString());
    assertEquals(0, compiled, "javac: " + javacOutput.toString(StandardCharsets.UTF_8));

    List<Path> runtime = new ArrayList<>(primeModules);
    runtime.add(classes);
    runtime.add(location(Class.forName("org.slf4j.simple.SimpleServiceProvider")));
    String java = Path.of(System.getProperty("java.home"), "bin", "java").toString();
    Process process =
        new ProcessBuilder(
                java, "-Xmx128m",
                "--module-path", joined(runtime),
                "-m", "prime.modulepath.app/app.Main")
            .redirectErrorStream(true)
            .start();
    String output;
    try {
      assertTrue(process.waitFor(60, TimeUnit.SECONDS), "the application did not end in 60 s");
      output = new String(process.getInputStream().readAllBytes(), StandardCharsets.UTF_8);
    } finally {
      process.destroyForcibly();
    }

    assertEquals(0, process.exitValue(), output);
    assertTrue(output.contains("MODULES prime.modulepath.app dev.prime"), output);
    assertTrue(output.contains("RESULT LibertyCore 42"), output);
    assertTrue(output.contains("RESULT RadiantCore 42"), output);
    // Prime's own log lines reach the provider: SLF4J was resolved and its provider bound
    assertFalse(output.contains("No SLF4J providers"), output);
    assertTrue(output.contains("INFO dev.prime"), output);
  }

  private static Path location(Class<?> type) throws URISyntaxException {
    return Path.of(type.getProtectionDomain().getCodeSource().getLocation().toURI());
  }

  private static String joined(List<Path> paths) {
    return paths.stream().map(Path::toString).collect(Collectors.joining(File.pathSeparator));
  }
}
