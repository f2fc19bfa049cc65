package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.stream.Collectors;
import java.util.stream.Stream;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A robot written as a named module of its own ({@code com.robot}, on the module path with
 * Prime's modules, as the README says an application may be) runs fused chains of its blocks: a
 * block in an exported package is called by its own class, one in a package the module keeps to
 * itself through {@code Block}, and a failing block reaches the caller as a {@code
 * ChainFailedException} naming its chain, the block's frame directly under the fused class. The
 * same program on Liberty prints the same results. The program is compiled with the JDK's javac
 * and run in a JVM of its own (a test's own classes are patched into Radiant's module, so only a
 * separate JVM has a user module in its boot layer).
 */
class UserModuleTest {
  private static final long LIMIT_SECONDS = 90;

  @Test
  void aRobotInANamedModuleOfItsOwnRunsFusedChainsOfItsBlocks(@TempDir Path dir)
      throws IOException, InterruptedException {
    Path sources = dir.resolve("src");
    write(sources, "module-info.java", """
        module com.robot {
          requires transitive dev.prime.radiant;
          requires dev.prime.liberty;
          exports com.robot.api;
        }
        """);
    write(sources, "com/robot/api/Scale.java", """
        package com.robot.api;
        public final class Scale implements dev.prime.Block<Integer, Integer> {
          public Scale() {}
          @Override public Integer process(Integer x) { return x * 10; }
        }
        """);
    write(sources, "com/robot/inner/Offset.java", """
        package com.robot.inner;
        public final class Offset implements dev.prime.Block<Integer, Integer> {
          @Override public Integer process(Integer x) { return x + 1; }
        }
        """);
    write(sources, "com/robot/inner/Unplugged.java", """
        package com.robot.inner;
        public final class Unplugged implements dev.prime.Block<Integer, Integer> {
          @Override public Integer process(Integer x) {
            throw new IllegalStateException("sensor " + x + " unplugged");
          }
        }
        """);
    write(sources, "com/robot/api/Main.java", """
        package com.robot.api;
        import dev.prime.Block;
        import dev.prime.ChainFailedException;
        import dev.prime.PrimeCore;
        import com.robot.inner.Offset;
        import com.robot.inner.Unplugged;
        import java.util.Arrays;
        import java.util.stream.Collectors;
        public final class Main {
          private Main() {}
          public static void main(String[] args) {
            System.out.println("module " + Main.class.getModule().getName());
            run(new dev.prime.radiant.RadiantCore());
            run(new dev.prime.liberty.LibertyCore());
          }
          private static void run(PrimeCore core) {
            try (core) {
              Block<Integer, Integer> block =
                  core.chain("scale", new Scale())
                      .then(core.chain("offset", new Offset()))
                      .then(core.chain("trim", (Integer x) -> x - 2))
                      .toBlock();
              System.out.println(core.name() + " result " + block.process(4));
              if (core instanceof dev.prime.radiant.RadiantCore) {
                System.out.println("fields " + Arrays.stream(block.getClass().getDeclaredFields())
                    .map(f -> f.getType().getName()).sorted().collect(Collectors.joining(",")));
              }
              Block<Integer, Integer> failing =
                  core.chain("scale2", new Scale()).then(core.chain("unplugged", new Unplugged()))
                      .toBlock();
              try {
                failing.process(7);
                System.out.println(core.name() + " no failure");
              } catch (ChainFailedException e) {
                Throwable cause = e.getCause();
                StackTraceElement[] trace = cause.getStackTrace();
                System.out.println(core.name() + " failed " + e.chainName() + " " + cause);
                System.out.println(core.name() + " thrown by " + trace[0].getClassName());
                int caller = 1;
                while (trace[caller].getClassName().equals(trace[0].getClassName())) {
                  caller++; // the block's bridge method
                }
                System.out.println(core.name() + " called from "
                    + trace[caller].getClassName().replaceAll("_[0-9]+$", "_<n>"));
              }
            }
          }
        }
        """);
    Path classes = dir.resolve("classes");
    String modulePath = primeModulePath();
    List<String> javac = new ArrayList<>(List.of(
        tool("javac"), "-d", classes.toString(), "--module-path", modulePath, "-Xlint:all",
        "-Werror"));
    try (Stream<Path> files = Files.walk(sources)) {
      javac.addAll(files.filter(p -> p.toString().endsWith(".java")).map(Path::toString)
          .collect(Collectors.toList()));
    }
    run(javac, dir.resolve("javac.log"));

    List<String> lines = run(
        List.of(tool("java"), "--module-path", classes + java.io.File.pathSeparator + modulePath,
            "-m", "com.robot/com.robot.api.Main"),
        dir.resolve("java.log"));

    assertEquals(
        List.of(
            "module com.robot",
            "radiant-1 result 39",
            "fields com.robot.api.Scale,dev.prime.Block,dev.prime.Block",
            "radiant-1 failed unplugged java.lang.IllegalStateException: sensor 70 unplugged",
            "radiant-1 thrown by com.robot.inner.Unplugged",
            "radiant-1 called from dev.prime.radiant.fused.Fused_scale2_unplugged_<n>",
            "liberty-1 result 39",
            "liberty-1 failed unplugged java.lang.IllegalStateException: sensor 70 unplugged",
            "liberty-1 thrown by com.robot.inner.Unplugged",
            "liberty-1 called from dev.prime.liberty.Runs$Run2"),
        lines);
  }

  /**
   * The robot's module path: where this JVM found Prime's modules and what they require (Liberty,
   * which Radiant does not read, is a test dependency on the class path: where its classes are).
   */
  private static String primeModulePath() throws IOException {
    List<String> entries = new ArrayList<>();
    for (String name : List.of("dev.prime", "dev.prime.radiant", "net.bytebuddy", "org.slf4j")) {
      entries.add(Path.of(ModuleLayer.boot().configuration().findModule(name)
          .orElseThrow(() -> new AssertionError(name + " is not in this test's boot layer"))
          .reference().location().orElseThrow()).toString());
    }
    try {
      entries.add(Path.of(dev.prime.liberty.LibertyCore.class.getProtectionDomain()
          .getCodeSource().getLocation().toURI()).toString());
    } catch (java.net.URISyntaxException e) {
      throw new IOException("Liberty's classes were loaded from no path", e);
    }
    return String.join(java.io.File.pathSeparator, entries);
  }

  private static String tool(String name) {
    Path tool = Path.of(System.getProperty("java.home"), "bin", name);
    assertTrue(Files.isExecutable(tool), "the JDK running the tests has " + tool);
    return tool.toString();
  }

  private static void write(Path root, String file, String text) throws IOException {
    Path path = root.resolve(file);
    Files.createDirectories(path.getParent());
    Files.writeString(path, text, StandardCharsets.UTF_8);
  }

  /** Runs a command to its end (at most {@link #LIMIT_SECONDS}); its standard output's lines. */
  private static List<String> run(List<String> command, Path errors)
      throws IOException, InterruptedException {
    Path output = errors.resolveSibling(errors.getFileName() + ".out");
    Process process =
        new ProcessBuilder(command)
            .redirectOutput(output.toFile())
            .redirectError(errors.toFile())
            .start();
    try {
      assertTrue(process.waitFor(LIMIT_SECONDS, TimeUnit.SECONDS),
          String.join(" ", command) + " did not end within " + LIMIT_SECONDS + " s");
    } finally {
      process.destroyForcibly();
    }
    assertEquals(0, process.exitValue(),
        String.join(" ", command) + " failed:\n" + Files.readString(errors)
            + Files.readString(output));
    return Files.readAllLines(output);
  }
}
