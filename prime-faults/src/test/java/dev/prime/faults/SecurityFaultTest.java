package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.optimus.OptimusCore;
import java.io.File;
import java.io.IOException;
import java.io.InputStream;
import java.io.PrintWriter;
import java.io.StringWriter;
import java.net.InetAddress;
import java.net.ServerSocket;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.attribute.PosixFilePermissions;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.HashMap;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Locale;
import java.util.Map;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;
import redis.clients.jedis.Jedis;

/**
 * Doors left open (issue 9 items 11 and 12): a same-size file planted where the bundled
 * redis-server is extracted is never executed; and no message or cause of any failure to reach
 * Redis ever shows the password, whatever characters it has.
 */
class SecurityFaultTest {
  private static final String SECRET = "SECRET";

  @Test
  void aPlantedRedisServerBinaryIsNotExecuted(@TempDir Path tmp) throws Exception {
    String resource = "redis-server-7.0.15-" + os() + "-" + arch();
    long size;
    try (InputStream bundled = OptimusCore.class.getResourceAsStream("/" + resource)) {
      if (bundled == null) throw new AssertionError("no bundled " + resource + " on the class path");
      size = bundled.transferTo(java.io.OutputStream.nullOutputStream());
    }
    // where main extracted it (a directory shared by every user), and this user's own directory
    String user = System.getProperty("user.name").replaceAll("[^A-Za-z0-9._-]", "_");
    Map<String, Path> plants = new LinkedHashMap<>();
    plants.put("shared", tmp.resolve("prime-redis-7.0.15").resolve(resource));
    plants.put("private", tmp.resolve("prime-redis-7.0.15-" + user).resolve(resource));
    for (Map.Entry<String, Path> plant : plants.entrySet()) {
      Files.createDirectories(plant.getValue().getParent(), PosixFilePermissions.asFileAttribute(PosixFilePermissions.fromString("rwx------")));
      plant(plant.getValue(), tmp.resolve("executed-" + plant.getKey()), size);
    }
    Map<String, String> environment = new HashMap<>();
    environment.put("PATH", pathWithoutRedis());
    String outcome;
    try (WorkerJvm worker = WorkerJvm.start("embedded", List.of("-Djava.io.tmpdir=" + tmp), environment, List.of("embedded"))) {
      outcome = worker.awaitLine(line -> line.startsWith("STARTED") || line.startsWith("FAILED"), FaultMode.PATIENCE)
          .orElse("(no answer) " + worker.output());
      worker.awaitExit(FaultMode.PATIENCE);
    }
    List<String> executed = new ArrayList<>();
    for (String name : plants.keySet()) if (Files.exists(tmp.resolve("executed-" + name))) executed.add(name);
    Figures.report("planted redis-server (" + size + " bytes, in the shared and in the user's directory): executed "
        + executed.size() + " time(s) " + executed + "; the embedded Redis " + outcome);
    assertEquals(List.of(), executed, "a planted binary was executed");
    assertTrue(outcome.startsWith("STARTED") && outcome.endsWith("PONG") || outcome.contains("SHA-256"),
        "either the real server runs or the start is refused for its checksum: " + outcome);
  }

  @Test
  void noMessageOrCauseShowsThePassword() throws Exception {
    int closed = closedPort();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null)) {
      try (Jedis raw = redis.client()) {
        raw.configSet("requirepass", "the-right-one");
      }
      List<String> urls = List.of(
          "redis://robot:" + SECRET + "%zz" + SECRET + "@127.0.0.1:" + closed,
          "redis://robot:" + SECRET + " " + SECRET + "@127.0.0.1:" + closed,
          "redis://robot:" + SECRET + "/" + SECRET + "@127.0.0.1:" + closed,
          "redis://robot:" + SECRET + "@" + SECRET + "@127.0.0.1:" + closed,
          "redis://:" + SECRET + "%2F" + SECRET + "@127.0.0.1:" + closed,
          "rediss://robot:" + SECRET + "@127.0.0.1:" + closed,
          "redis://:" + SECRET + "@127.0.0.1:" + redis.port(),
          "redis://default:" + SECRET + "%40x@127.0.0.1:" + redis.port());
      List<String> leaks = new ArrayList<>();
      List<String> outcomes = new ArrayList<>();
      for (String url : urls) {
        String text;
        try (OptimusCore core = OptimusCore.builder().redis(url).build()) {
          text = "(connected: " + core + ")";
        } catch (RuntimeException e) {
          text = everything(e);
        }
        outcomes.add(text.lines().findFirst().orElse(""));
        if (text.contains(SECRET)) leaks.add(url.replace(SECRET, "<password>") + " -> " + text.lines().filter(l -> l.contains(SECRET)).findFirst().orElse(""));
      }
      Figures.report("passwords: " + urls.size() + " URLs (%, space, /, @ in the password; unreachable port; TLS; wrong password), "
          + leaks.size() + " messages showing the password");
      assertEquals(List.of(), leaks, "messages or causes that show the password; all outcomes:\n" + String.join("\n", outcomes));
      for (String outcome : outcomes) assertFalse(outcome.startsWith("(connected"), outcome);
    }
  }

  /** The stack trace with every cause and suppressed exception, as a log would print it. */
  private static String everything(Throwable e) {
    StringWriter text = new StringWriter();
    e.printStackTrace(new PrintWriter(text));
    return text.toString();
  }

  /** A shell script of exactly {@code size} bytes that leaves {@code marker} and fails. */
  private static void plant(Path file, Path marker, long size) throws IOException {
    String script = "#!/bin/sh\necho planted > '" + marker + "'\nexit 1\n";
    byte[] bytes = new byte[(int) size];
    Arrays.fill(bytes, (byte) '#');
    byte[] head = script.getBytes(StandardCharsets.UTF_8);
    System.arraycopy(head, 0, bytes, 0, head.length);
    bytes[bytes.length - 1] = '\n';
    Files.write(file, bytes);
    Files.setPosixFilePermissions(file, PosixFilePermissions.fromString("rwx------"));
  }

  /** The PATH without any directory that holds a redis-server, so the bundled one is used. */
  private static String pathWithoutRedis() {
    String path = System.getenv().getOrDefault("PATH", "/usr/bin:/bin");
    return Arrays.stream(path.split(File.pathSeparator))
        .filter(dir -> !dir.isEmpty() && !Files.isExecutable(Path.of(dir, "redis-server")))
        .collect(Collectors.joining(File.pathSeparator));
  }

  private static int closedPort() throws IOException {
    try (ServerSocket socket = new ServerSocket(0, 1, InetAddress.getLoopbackAddress())) {
      return socket.getLocalPort();
    }
  }

  private static String os() {
    String name = System.getProperty("os.name").toLowerCase(Locale.ROOT);
    return name.contains("mac") || name.contains("darwin") ? "darwin" : "linux";
  }

  private static String arch() {
    String arch = System.getProperty("os.arch").toLowerCase(Locale.ROOT);
    switch (arch) {
      case "amd64":
      case "x86_64":
        return "amd64";
      case "aarch64":
      case "arm64":
        return "arm64";
      default:
        return arch;
    }
  }
}
