package dev.prime.inspector;

import static org.junit.jupiter.api.Assumptions.assumeTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import com.fasterxml.jackson.databind.node.ObjectNode;
import java.io.File;
import java.io.IOException;
import java.net.URI;
import java.net.http.HttpClient;
import java.net.http.HttpRequest;
import java.net.http.HttpResponse;
import java.net.http.WebSocket;
import java.nio.file.Files;
import java.nio.file.Path;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Base64;
import java.util.Comparator;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CompletionStage;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.function.Predicate;
import java.util.stream.Stream;

/**
 * A headless Chromium for tests, driven over the DevTools protocol with the JDK's WebSocket
 * client: {@link #evaluate(String)} runs JavaScript in the page and returns its value as JSON.
 *
 * <p>Design note. Chromium is started with {@code --remote-debugging-port=0} and a fresh profile
 * directory, in which it writes the port it chose ({@code DevToolsActivePort}); the page's
 * WebSocket is found through {@code /json/list}. Every wait is bounded. {@link #close()} kills
 * the whole process tree (the browser and every renderer, GPU and zygote process it started,
 * listed before the browser is killed, since they are re-parented after), waits for them, and
 * deletes the profile; it is safe after any failure.
 */
public final class HeadlessChromium implements AutoCloseable {
  private static final Duration START_PATIENCE = Duration.ofSeconds(30);
  private static final Duration CALL_PATIENCE = Duration.ofSeconds(20);
  private static final ObjectMapper JSON = new ObjectMapper();

  private final Process process;
  private final Path profile;
  private final Path log;
  private final HttpClient http;
  private WebSocket socket;
  private final Map<Integer, CompletableFuture<JsonNode>> calls = new ConcurrentHashMap<>();
  private final AtomicInteger ids = new AtomicInteger();

  private HeadlessChromium(Process process, Path profile, Path log) {
    this.process = process;
    this.profile = profile;
    this.log = log;
    this.http = HttpClient.newBuilder().connectTimeout(Duration.ofSeconds(5)).build();
  }

  /**
   * The Chromium binary: the system property {@code prime.chromium}, or {@code chromium}, {@code
   * chromium-browser}, {@code google-chrome} on the PATH.
   */
  public static Optional<Path> binary() {
    String configured = System.getProperty("prime.chromium");
    if (configured != null && !configured.isBlank()) {
      return Optional.of(Path.of(configured)).filter(Files::isExecutable);
    }
    String path = System.getenv().getOrDefault("PATH", "");
    for (String name : List.of("chromium", "chromium-browser", "google-chrome")) {
      for (String dir : path.split(File.pathSeparator)) {
        if (!dir.isEmpty()) {
          Path candidate = Path.of(dir, name);
          if (Files.isExecutable(candidate)) {
            return Optional.of(candidate);
          }
        }
      }
    }
    return Optional.empty();
  }

  /** Skips the calling test, with the reason, when there is no Chromium. */
  public static Path requireBinary() {
    Optional<Path> binary = binary();
    assumeTrue(
        binary.isPresent(),
        "no Chromium found (chromium, chromium-browser or google-chrome on the PATH, or"
            + " -Dprime.chromium=/path/to/chrome): the browser test of the inspector's page is"
            + " skipped. Install one (Debian: apt-get install chromium) to run it.");
    return binary.get();
  }

  /**
   * Starts Chromium showing {@code url}, with a window of the given size.
   */
  public static HeadlessChromium open(URI url, int width, int height) throws IOException, InterruptedException {
    Path binary = requireBinary();
    Path profile = Files.createTempDirectory("prime-inspector-chromium-");
    Path log = profile.resolveSibling(profile.getFileName() + ".log");
    List<String> command =
        List.of(
            binary.toString(),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-dev-shm-usage",
            "--hide-scrollbars",
            "--window-size=" + width + "," + height,
            "--user-data-dir=" + profile,
            "--remote-debugging-address=127.0.0.1",
            "--remote-debugging-port=0",
            url.toString());
    Process process =
        new ProcessBuilder(command)
            .redirectErrorStream(true)
            .redirectOutput(log.toFile())
            .redirectInput(ProcessBuilder.Redirect.from(new File("/dev/null")))
            .start();
    HeadlessChromium chromium = new HeadlessChromium(process, profile, log);
    try {
      chromium.connect(url);
      return chromium;
    } catch (IOException | InterruptedException | RuntimeException | AssertionError e) {
      chromium.close();
      throw e;
    }
  }

  private void connect(URI url) throws IOException, InterruptedException {
    long deadline = System.nanoTime() + START_PATIENCE.toNanos();
    Path portFile = profile.resolve("DevToolsActivePort");
    int port = -1;
    while (port < 0) {
      if (!process.isAlive()) {
        throw new AssertionError("Chromium ended at its start (exit " + process.exitValue() + "): " + logTail());
      }
      if (Files.isRegularFile(portFile)) {
        List<String> lines = Files.readAllLines(portFile);
        if (!lines.isEmpty() && !lines.get(0).isBlank()) {
          port = Integer.parseInt(lines.get(0).trim());
          break;
        }
      }
      if (System.nanoTime() > deadline) {
        throw new AssertionError("Chromium did not open its DevTools port within " + START_PATIENCE + ": " + logTail());
      }
      Thread.sleep(50); // polling a file Chromium writes: nothing to wait on
    }
    String pageSocket = null;
    while (pageSocket == null) {
      HttpResponse<String> list =
          http.send(
              HttpRequest.newBuilder(URI.create("http://127.0.0.1:" + port + "/json/list"))
                  .timeout(Duration.ofSeconds(5))
                  .build(),
              HttpResponse.BodyHandlers.ofString());
      for (JsonNode target : JSON.readTree(list.body())) {
        if (target.path("type").asText().equals("page")
            && target.path("url").asText().startsWith("http://" + url.getRawAuthority() + "/")) {
          pageSocket = target.path("webSocketDebuggerUrl").asText();
        }
      }
      if (pageSocket == null) {
        if (System.nanoTime() > deadline) {
          throw new AssertionError("Chromium shows no page at " + url + ": " + list.body());
        }
        Thread.sleep(50);
      }
    }
    try {
      socket =
          http.newWebSocketBuilder()
              .buildAsync(URI.create(pageSocket), new Listener())
              .get(CALL_PATIENCE.toSeconds(), TimeUnit.SECONDS);
    } catch (ExecutionException | TimeoutException e) {
      throw new AssertionError("cannot open Chromium's DevTools socket " + pageSocket + ": " + e, e);
    }
  }

  private String logTail() {
    try {
      List<String> lines = Files.readAllLines(log);
      return String.join("\n", lines.subList(Math.max(0, lines.size() - 20), lines.size()));
    } catch (IOException e) {
      return "(no log: " + e + ")";
    }
  }

  /** Collects the text frames of one message and completes the call its id answers. */
  private final class Listener implements WebSocket.Listener {
    private final StringBuilder message = new StringBuilder();

    @Override
    public CompletionStage<?> onText(WebSocket webSocket, CharSequence data, boolean last) {
      message.append(data);
      if (last) {
        String text = message.toString();
        message.setLength(0);
        try {
          JsonNode answer = JSON.readTree(text);
          if (answer.has("id")) {
            CompletableFuture<JsonNode> call = calls.remove(answer.get("id").asInt());
            if (call != null) {
              call.complete(answer);
            }
          }
        } catch (IOException e) {
          calls.values().forEach(call -> call.completeExceptionally(e));
        }
      }
      webSocket.request(1);
      return null;
    }

    @Override
    public void onError(WebSocket webSocket, Throwable error) {
      calls.values().forEach(call -> call.completeExceptionally(error));
    }
  }

  /** Sends a DevTools command and returns its {@code result}; a protocol error fails the test. */
  public JsonNode call(String method, Map<String, Object> params) throws InterruptedException {
    int id = ids.incrementAndGet();
    CompletableFuture<JsonNode> answer = new CompletableFuture<>();
    calls.put(id, answer);
    ObjectNode command = JSON.createObjectNode().put("id", id).put("method", method);
    command.set("params", JSON.valueToTree(params));
    try {
      socket.sendText(command.toString(), true).get(CALL_PATIENCE.toSeconds(), TimeUnit.SECONDS);
      JsonNode result = answer.get(CALL_PATIENCE.toSeconds(), TimeUnit.SECONDS);
      if (result.has("error")) {
        throw new AssertionError(method + " failed: " + result.get("error"));
      }
      return result.get("result");
    } catch (ExecutionException | TimeoutException e) {
      throw new AssertionError(method + " got no answer from Chromium within " + CALL_PATIENCE + ": " + e, e);
    } finally {
      calls.remove(id);
    }
  }

  /** Runs {@code expression} in the page (awaiting a promise) and returns its value as JSON. */
  public JsonNode evaluate(String expression) throws InterruptedException {
    JsonNode result =
        call("Runtime.evaluate",
            Map.of("expression", expression, "returnByValue", true, "awaitPromise", true));
    if (result.has("exceptionDetails")) {
      throw new AssertionError("the page threw for " + expression + ": " + result.get("exceptionDetails"));
    }
    return result.path("result").path("value");
  }

  /**
   * Evaluates {@code expression} until its value passes {@code test}, at most {@code patience};
   * returns that value, or fails with the last value seen.
   */
  public JsonNode await(String expression, Predicate<JsonNode> test, Duration patience, String what)
      throws InterruptedException {
    long deadline = System.nanoTime() + patience.toNanos();
    while (true) {
      Object seen;
      try {
        JsonNode value = evaluate(expression);
        if (test.test(value)) {
          return value;
        }
        seen = value;
      } catch (AssertionError pageThrew) { // the page may not have made the element yet
        seen = pageThrew.getMessage();
      }
      if (System.nanoTime() > deadline) {
        throw new AssertionError("within " + patience + ", " + what + "; the page's last answer: " + seen);
      }
      Thread.sleep(100); // the page changes on its own; nothing to wait on but the next look
    }
  }

  /** Writes a PNG of the whole page (beyond the window, if it is longer) as it shows now. */
  public void screenshot(Path file) throws InterruptedException, IOException {
    JsonNode size = evaluate("[document.documentElement.scrollWidth, document.documentElement.scrollHeight]");
    Map<String, Object> clip =
        Map.of("x", 0, "y", 0, "width", size.get(0).asInt(), "height", size.get(1).asInt(), "scale", 1);
    JsonNode shot =
        call("Page.captureScreenshot", Map.of("format", "png", "captureBeyondViewport", true, "clip", clip));
    Files.write(file, Base64.getDecoder().decode(shot.get("data").asText()));
  }

  /** {@return the processes Chromium runs now: the browser and its descendants} */
  public List<ProcessHandle> processes() {
    List<ProcessHandle> all = new ArrayList<>();
    all.add(process.toHandle());
    process.descendants().forEach(all::add);
    return all;
  }

  @Override
  public void close() {
    List<ProcessHandle> all = processes();
    if (socket != null) {
      socket.abort();
    }
    all.forEach(ProcessHandle::destroy);
    long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(5);
    for (ProcessHandle handle : all) {
      try {
        handle.onExit().get(Math.max(1, deadline - System.nanoTime()), TimeUnit.NANOSECONDS);
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
        break;
      } catch (ExecutionException | TimeoutException e) {
        handle.destroyForcibly();
      }
    }
    for (ProcessHandle handle : all) {
      if (handle.isAlive()) {
        handle.destroyForcibly();
        try {
          handle.onExit().get(5, TimeUnit.SECONDS);
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
        } catch (ExecutionException | TimeoutException e) {
          // reported by the tests that count Chromium's processes
        }
      }
    }
    deleteQuietly(profile);
    deleteQuietly(log);
  }

  private static void deleteQuietly(Path path) {
    if (!Files.exists(path)) {
      return;
    }
    try (Stream<Path> walk = Files.walk(path)) {
      walk.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
    } catch (IOException | RuntimeException e) {
      // a temporary directory left behind is not worth failing a test for
    }
  }
}
