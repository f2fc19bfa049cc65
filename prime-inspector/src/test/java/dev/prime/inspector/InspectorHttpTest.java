package dev.prime.inspector;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.io.IOException;
import java.io.InputStream;
import java.io.OutputStream;
import java.io.UncheckedIOException;
import java.net.HttpURLConnection;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.Socket;
import java.net.URI;
import java.net.URLEncoder;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.List;
import java.util.Set;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.concurrent.locks.LockSupport;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;

/** The inspector's answers over plain HTTP: pages, JSON, event streams, refusals, shutdown. */
class InspectorHttpTest {
  private static final ObjectMapper JSON = new ObjectMapper();

  record Answer(int status, String contentType, String body) {}

  static Answer get(URI uri, String path) throws IOException {
    return request(uri, path, "GET");
  }

  private static Answer request(URI uri, String path, String method) throws IOException {
    // not URI.resolve: a test sends malformed paths too
    HttpURLConnection connection =
        (HttpURLConnection) new java.net.URL(uri + path.substring(1)).openConnection();
    connection.setRequestMethod(method);
    connection.setConnectTimeout(5_000);
    connection.setReadTimeout(10_000);
    try {
      int status = connection.getResponseCode();
      InputStream in = status < 400 ? connection.getInputStream() : connection.getErrorStream();
      String body = in == null ? "" : new String(in.readAllBytes(), StandardCharsets.UTF_8);
      return new Answer(status, connection.getContentType(), body);
    } finally {
      connection.disconnect();
    }
  }

  private static String encoded(String name) {
    return URLEncoder.encode(name, StandardCharsets.UTF_8).replace("+", "%20");
  }

  private static CoreConfig recording() {
    return CoreConfig.builder().name("demo").recording(RecordingOptions.defaults()).build();
  }

  @Test
  void servesThePageItsScriptAndTheTopology() throws Exception {
    try (PrimeCore core = new LibertyCore(recording());
        PrimeInspector inspector = PrimeInspector.start(DemoController.declaredOn(core))) {
      assertEquals("127.0.0.1", inspector.uri().getHost());
      Answer page = get(inspector.uri(), "/");
      assertEquals(200, page.status());
      assertTrue(page.contentType().startsWith("text/html"), page.contentType());
      assertTrue(page.body().contains("<svg id=\"diagram\""), page.body());
      assertFalse(page.body().matches("(?s).*(https?:)?//[a-z].*src=.*"), "no script from elsewhere");
      assertEquals(200, get(inspector.uri(), "/inspector.js").status());
      assertEquals(200, get(inspector.uri(), "/inspector.css").status());

      Answer topology = get(inspector.uri(), "/api/topology");
      assertEquals(200, topology.status());
      JsonNode json = JSON.readTree(topology.body());
      assertEquals("demo", json.get("core").asText());
      assertTrue(json.get("recording").asBoolean());
      List<String> services = new ArrayList<>();
      json.get("services").forEach(s -> services.add(s.asText()));
      assertEquals(List.copyOf(core.serviceNames()), services);
      Set<String> drawn =
          new java.util.HashSet<>(json.get("nodes").findValuesAsText("name"));
      assertTrue(drawn.containsAll(core.serviceNames()), drawn.toString());
      assertTrue(drawn.contains("encoders>odometry reader 1"), "the program's reader is drawn: " + drawn);
      assertFalse(drawn.contains("planner>pid"), "a link is an edge, not a box");
    }
  }

  @Test
  void aRecordedNameGivesItsValuesAndTheirNumbers() throws Exception {
    try (PrimeCore core = new LibertyCore(recording());
        DemoController demo = new DemoController(core);
        PrimeInspector inspector = PrimeInspector.start(core)) {
      core.start();
      demo.drive(1);
      long deadline = System.nanoTime() + 10_000_000_000L;
      while (core.recording().recorded("odometry") < 3 && System.nanoTime() < deadline) {
        Thread.sleep(10); // polling the recording, bounded by the deadline
      }
      demo.stop();
      long recorded = core.recording().recorded("odometry");
      assertTrue(recorded >= 3, "odometry recorded " + recorded + " values in 10 s");
      Answer values = get(inspector.uri(), "/api/values/odometry");
      assertEquals(200, values.status(), values.body());
      JsonNode json = JSON.readTree(values.body());
      assertEquals("odometry", json.get("service").asText());
      JsonNode points = json.get("points");
      assertEquals(Math.min(recorded, 300), points.size());
      JsonNode last = points.get(points.size() - 1);
      DemoController.Estimate estimate = core.recording().get("odometry");
      assertEquals(estimate.x(), last.get("fields").get("x").asDouble());
      assertEquals(estimate.y(), last.get("fields").get("y").asDouble());
      assertEquals(estimate.moving() ? 1.0 : 0.0, last.get("fields").get("moving").asDouble());
    }
  }

  @Test
  void unknownNamesPagesAndMethodsAreRefusedWithTheReason() throws Exception {
    try (PrimeCore core = new LibertyCore(recording());
        PrimeInspector inspector = PrimeInspector.start(DemoController.declaredOn(core))) {
      Answer unknown = get(inspector.uri(), "/api/values/nowhere");
      assertEquals(404, unknown.status());
      assertTrue(unknown.body().contains("core 'demo' has no service, source or chain named 'nowhere'"), unknown.body());
      assertTrue(unknown.body().contains("odometry"), "the message lists the services: " + unknown.body());

      Answer stream = get(inspector.uri(), "/api/events/nowhere");
      assertEquals(404, stream.status());
      assertTrue(stream.body().contains("'nowhere'"), stream.body());

      Answer notRecorded = get(inspector.uri(), "/api/values/" + encoded("guard(planner>pid)"));
      assertEquals(404, notRecorded.status());
      assertTrue(notRecorded.body().contains("'guard(planner>pid)' is not recorded"), notRecorded.body());
      assertTrue(notRecorded.body().contains("recorded: [encoders, odometry"), notRecorded.body());

      Answer page = get(inspector.uri(), "/admin");
      assertEquals(404, page.status());
      assertTrue(page.body().contains("no page at /admin"), page.body());

      Answer badEscape = get(inspector.uri(), "/api/values/%zz"); // refused by the JDK's server
      assertEquals(400, badEscape.status());

      Answer post = request(inspector.uri(), "/api/topology", "POST");
      assertEquals(405, post.status());
      assertTrue(post.body().contains("GET only"), post.body());
    }
  }

  @Test
  void withRecordingOffValuesAreRefusedAndTheTopologySaysSo() throws Exception {
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().name("quiet").build());
        PrimeInspector inspector = PrimeInspector.start(DemoController.declaredOn(core))) {
      Answer values = get(inspector.uri(), "/api/values/odometry");
      assertEquals(409, values.status());
      assertTrue(values.body().contains("records nothing"), values.body());
      assertTrue(values.body().contains("RecordingOptions.defaults()"), values.body());
      Answer unknown = get(inspector.uri(), "/api/values/nowhere");
      assertEquals(404, unknown.status(), "a name that is no node of the core: " + unknown.body());
      assertTrue(unknown.body().contains("no service, source or chain named 'nowhere'"), unknown.body());
      JsonNode topology = JSON.readTree(get(inspector.uri(), "/api/topology").body());
      assertFalse(topology.get("recording").asBoolean());
      assertTrue(topology.get("figures").asText().contains("recording"), topology.toString());
    }
  }

  @Test
  void aTakenPortIsRefusedWithTheAddress() throws Exception {
    try (PrimeCore core = new LibertyCore();
        PrimeInspector first = PrimeInspector.start(core)) {
      InetSocketAddress taken = new InetSocketAddress("127.0.0.1", first.uri().getPort());
      UncheckedIOException refused =
          assertThrows(UncheckedIOException.class, () -> PrimeInspector.start(core, taken));
      assertTrue(refused.getMessage().contains(String.valueOf(taken.getPort())), refused.getMessage());
      assertTrue(refused.getMessage().contains("port 0 picks a free one"), refused.getMessage());
    }
  }

  /**
   * An inspector bound to the wildcard address (every interface) gives the loopback address in
   * its uri(), which this machine reaches, not the wildcard, which is no address to open.
   */
  @Test
  void anInspectorOnTheWildcardAddressGivesALoopbackUri() throws Exception {
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(recording()))) {
      for (String wildcard : List.of("0.0.0.0", "::")) {
        try (PrimeInspector inspector =
            PrimeInspector.start(core, new InetSocketAddress(InetAddress.getByName(wildcard), 0))) {
          URI uri = inspector.uri();
          assertTrue(
              InetAddress.getByName(uri.getHost().replace("[", "").replace("]", "")).isLoopbackAddress(),
              "bound to " + wildcard + ", the page's address is " + uri);
          assertEquals(200, get(uri, "/api/topology").status(), "the page at " + uri);
        }
      }
    }
  }

  @Test
  void anUnresolvedAddressIsRefusedSayingWhatToGiveAndNoThreadIsLeft() throws Exception {
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(recording()))) {
      InetSocketAddress unresolved = InetSocketAddress.createUnresolved("robot.invalid", 8080);
      UncheckedIOException refused =
          assertThrows(UncheckedIOException.class, () -> PrimeInspector.start(core, unresolved));
      assertTrue(refused.getMessage().contains("the host name 'robot.invalid' is not resolved"), refused.getMessage());
      assertFalse(refused.getMessage().contains("port"), "the port is not the problem: " + refused.getMessage());
      assertTrue(refused.getMessage().contains("like new InetSocketAddress(\"127.0.0.1\", 8080)"), refused.getMessage());
      assertEquals(Set.of(), inspectorThreads(), "threads left by the refused start");
    }
  }

  @Test
  void anAddressNotOfThisMachineIsRefusedSayingSoAndNoThreadIsLeft() throws Exception {
    // 192.0.2.1 is reserved for documentation (TEST-NET-1): no machine has it, and a refused bind sends nothing.
    InetSocketAddress elsewhere = new InetSocketAddress(InetAddress.getByAddress(new byte[] {(byte) 192, 0, 2, 1}), 8080);
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(recording()))) {
      UncheckedIOException refused =
          assertThrows(UncheckedIOException.class, () -> PrimeInspector.start(core, elsewhere));
      assertTrue(refused.getMessage().contains("192.0.2.1 is not an address of this machine"), refused.getMessage());
      assertFalse(refused.getMessage().contains("port taken"), "the port is not the problem: " + refused.getMessage());
      assertTrue(refused.getMessage().contains("like new InetSocketAddress(\"127.0.0.1\", 8080)"), refused.getMessage());
      assertEquals(Set.of(), inspectorThreads(), "threads left by the refused start");
    }
  }

  /**
   * Reads one server-sent event stream over a plain socket (no client library, so no threads of
   * its own): the status line and headers, then the body's lines, decoding the chunked transfer
   * encoding the server streams with.
   */
  static final class RawStream implements AutoCloseable {
    private final Socket socket;
    private final InputStream in;
    private boolean inBody;
    private boolean ended;
    private long chunkLeft;

    RawStream(URI uri, String path) throws IOException {
      socket = new Socket("127.0.0.1", uri.getPort());
      socket.setSoTimeout(10_000);
      OutputStream out = socket.getOutputStream();
      out.write(("GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n")
          .getBytes(StandardCharsets.US_ASCII));
      out.flush();
      in = new java.io.BufferedInputStream(socket.getInputStream());
    }

    /** The next line (a header line, then a line of the body), or null at the end. */
    String line() throws IOException {
      java.io.ByteArrayOutputStream line = new java.io.ByteArrayOutputStream();
      while (true) {
        int b = inBody ? bodyByte() : in.read();
        if (b < 0) {
          return line.size() == 0 ? null : line.toString(StandardCharsets.UTF_8);
        }
        if (b == '\n') {
          String text = line.toString(StandardCharsets.UTF_8);
          if (text.endsWith("\r")) {
            text = text.substring(0, text.length() - 1);
          }
          if (!inBody && text.isEmpty()) {
            inBody = true; // the blank line after the headers
          }
          return text;
        }
        line.write(b);
      }
    }

    private int bodyByte() throws IOException {
      if (ended) {
        return -1;
      }
      if (chunkLeft == 0) {
        String size = rawLine();
        if (size != null && size.isEmpty()) {
          size = rawLine(); // the CRLF that ends the previous chunk
        }
        if (size == null) {
          ended = true;
          return -1;
        }
        chunkLeft = Long.parseLong(size.split(";")[0].trim(), 16);
        if (chunkLeft == 0) {
          ended = true;
          return -1;
        }
      }
      int b = in.read();
      if (b < 0) {
        ended = true;
        return -1;
      }
      chunkLeft--;
      return b;
    }

    private String rawLine() throws IOException {
      StringBuilder line = new StringBuilder();
      for (int b = in.read(); b >= 0; b = in.read()) {
        if (b == '\n') {
          return line.toString().strip();
        }
        line.append((char) b);
      }
      return line.length() == 0 ? null : line.toString();
    }

    /** Reads lines until one starts with {@code prefix}; fails after {@code limit} lines. */
    String until(String prefix, int limit) throws IOException {
      for (int i = 0; i < limit; i++) {
        String line = line();
        if (line == null) {
          throw new AssertionError("the stream ended before a line starting with " + prefix);
        }
        if (line.startsWith(prefix)) {
          return line;
        }
      }
      throw new AssertionError("no line starting with " + prefix + " in " + limit + " lines");
    }

    @Override
    public void close() throws IOException {
      socket.close();
    }
  }

  @Test
  void theEventStreamCarriesFiguresAndThePlottedValues() throws Exception {
    try (PrimeCore core = new LibertyCore(recording());
        DemoController demo = new DemoController(core);
        PrimeInspector inspector = PrimeInspector.start(core)) {
      core.start();
      demo.drive(2);
      try (RawStream stream = new RawStream(inspector.uri(), "/api/events/odometry")) {
        assertEquals("HTTP/1.1 200 OK", stream.line());
        String type = stream.until("Content-type:", 20);
        assertTrue(type.contains("text/event-stream"), type);
        JsonNode figures = null;
        for (int i = 0; i < 10 && (figures == null || !figures.get("started").asBoolean()); i++) {
          stream.until("event: figures", 50); // the first may be from before the start
          figures = JSON.readTree(stream.until("data: ", 5).substring(6));
        }
        assertTrue(figures.get("started").asBoolean(), figures.toString());
        assertTrue(figures.get("nodes").has("odometry"), figures.toString());
        stream.until("event: values", 50);
        JsonNode values = JSON.readTree(stream.until("data: ", 5).substring(6));
        assertEquals("odometry", values.get("service").asText());
        assertTrue(values.get("points").size() > 0);
        assertTrue(values.get("points").get(0).get("fields").has("x"), values.toString());
      } finally {
        demo.stop();
      }
    }
  }

  /** A value whose points are long in JSON: twelve numeric fields with long names and digits. */
  record Wide(
      double leftWheelPositionMetres, double rightWheelPositionMetres,
      double leftWheelVelocityMetres, double rightWheelVelocityMetres,
      double estimatedHeadingRadians, double estimatedPositionXMetres,
      double estimatedPositionYMetres, double commandedLeftMotorVolts,
      double commandedRightMotorVolts, double distanceToTheGoalMetres,
      double yawRateFromTheGyroscope, double lateralOffsetFromLine) {
    static Wide of(int i) {
      double v = i + Math.PI / 10;
      return new Wide(v, v, v, v, v, v, v, v, v, v, v, v);
    }
  }

  /** Whether {@code thread} is writing to a stream now (in {@code InspectorServer.write}). */
  private static boolean writing(Thread thread) {
    for (StackTraceElement frame : thread.getStackTrace()) {
      if (frame.getClassName().endsWith("InspectorServer") && frame.getMethodName().equals("write")) {
        return true;
      }
    }
    return false;
  }

  /**
   * A browser that stops reading its stream stalls that stream's thread in a write, and nothing
   * else: another page's stream goes on getting the figures twice a second, plain requests are
   * answered, and close() still ends every thread, the stalled one too.
   */
  @Test
  void aBrowserThatStopsReadingStallsOnlyItsOwnStream() throws Exception {
    try (PrimeCore core = new LibertyCore(recording())) {
      EventBlock<Integer> ticks = new EventBlock<>();
      core.source("ticks", ticks).then(core.chain("wide", Wide::of));
      PrimeInspector inspector = PrimeInspector.start(core);
      core.start();
      AtomicBoolean publishing = new AtomicBoolean(true);
      Thread publisher = new Thread(() -> {
        for (int i = 0; publishing.get() && i < 100_000_000; i++) {
          ticks.publish(i);
          LockSupport.parkNanos(200_000); // about 5000 values a second
        }
      }, "wide-publisher");
      publisher.start();
      Socket deaf = new Socket();
      try (inspector) {
        deaf.setReceiveBufferSize(1024);
        deaf.connect(new InetSocketAddress("127.0.0.1", inspector.uri().getPort()), 5_000);
        deaf.getOutputStream().write(("GET /api/events/wide HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
            .getBytes(StandardCharsets.US_ASCII));
        // never read: the server's writes fill the socket's buffers, then block
        Thread stalled = null;
        long deadline = System.nanoTime() + 60_000_000_000L;
        while (stalled == null) {
          assertTrue(System.nanoTime() < deadline, "the stream of a page that reads nothing never stalled in 60 s");
          Set<Thread> inWrite = Thread.getAllStackTraces().keySet().stream()
              .filter(t -> t.getName().startsWith("prime-inspector-demo-http-") && writing(t))
              .collect(Collectors.toSet());
          Thread.sleep(1_000); // a write that is still under way a second later is stalled
          stalled = inWrite.stream().filter(InspectorHttpTest::writing).findFirst().orElse(null);
        }

        try (RawStream other = new RawStream(inspector.uri(), "/api/events")) {
          assertEquals("HTTP/1.1 200 OK", other.line());
          long start = System.nanoTime();
          for (int i = 0; i < 4; i++) {
            other.until("event: figures", 50);
          }
          long millis = (System.nanoTime() - start) / 1_000_000;
          assertTrue(millis < 5_000, "4 postings to another page took " + millis + " ms");
        }
        assertEquals(200, get(inspector.uri(), "/api/topology").status(), "plain requests are answered");
        assertTrue(stalled.isAlive() && writing(stalled), "the deaf page's stream is still stalled");
      } finally {
        publishing.set(false);
        publisher.join(10_000);
        deaf.close();
      }
      assertEquals(Set.of(), inspectorThreads(), "threads left after close, the stalled one too");
    }
  }

  @Test
  void anInspectorThatOutlivesItsCoreShowsItClosed() throws Exception {
    CoreConfig config =
        CoreConfig.builder().name("brief").metrics(true).recording(RecordingOptions.defaults()).build();
    PrimeCore core = DemoController.declaredOn(new LibertyCore(config));
    try (PrimeInspector inspector = PrimeInspector.start(core)) {
      try (core) {
        core.start();
      }
      Answer topology = get(inspector.uri(), "/api/topology");
      assertEquals(200, topology.status(), topology.body());
      assertEquals("brief", JSON.readTree(topology.body()).get("core").asText());
      try (RawStream stream = new RawStream(inspector.uri(), "/api/events")) {
        assertEquals("HTTP/1.1 200 OK", stream.line());
        JsonNode figures = null;
        // the first posting may be from before the close; the sampler posts twice a second
        for (int i = 0; i < 10 && (figures == null || !figures.path("closed").asBoolean()); i++) {
          stream.until("event: figures", 50);
          figures = JSON.readTree(stream.until("data: ", 5).substring(6));
        }
        assertTrue(figures.path("closed").asBoolean(), "the figures say the core closed: " + figures);
        assertFalse(figures.has("error"), "a closed core is not an error: " + figures);
      }
    }
  }

  @Test
  void streamsBeyondTheLimitAreRefusedAndTheLimitFreesUpOnClose() throws Exception {
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(recording()));
        PrimeInspector inspector = PrimeInspector.start(core)) {
      List<RawStream> streams = new ArrayList<>();
      try {
        for (int i = 0; i < 32; i++) {
          RawStream stream = new RawStream(inspector.uri(), "/api/events");
          streams.add(stream);
          assertEquals("HTTP/1.1 200 OK", stream.line(), "stream " + (i + 1));
        }
        Answer refused = get(inspector.uri(), "/api/events");
        assertEquals(503, refused.status());
        assertTrue(refused.body().contains("32 event streams open already"), refused.body());
        assertEquals(200, get(inspector.uri(), "/api/topology").status(), "plain requests still served");

        streams.remove(0).close(); // the server notices at its next write, within a period or two
        long deadline = System.nanoTime() + 10_000_000_000L;
        while (true) {
          RawStream again = new RawStream(inspector.uri(), "/api/events");
          String status = again.line();
          if ("HTTP/1.1 200 OK".equals(status)) {
            streams.add(again);
            break;
          }
          again.close();
          assertTrue(System.nanoTime() < deadline, "a closed stream's place was not freed: " + status);
          Thread.sleep(100); // polling the server, bounded by the deadline
        }
      } finally {
        for (RawStream stream : streams) {
          stream.close();
        }
      }
    }
  }

  static Set<String> inspectorThreads() {
    return Thread.getAllStackTraces().keySet().stream()
        .filter(Thread::isAlive)
        .map(Thread::getName)
        .filter(name -> name.startsWith("prime-inspector-") || name.equals("HTTP-Dispatcher"))
        .collect(Collectors.toSet());
  }

  @Test
  void closeReturnsOnlyOnceEveryThreadItMadeHasEnded() throws Exception {
    // a pool counts as ended when its last task returned, a moment before the task's thread ends;
    // 50 rounds of answering a request and closing at once give that moment many chances to show
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(recording()))) {
      core.start();
      for (int round = 0; round < 50; round++) {
        PrimeInspector inspector = PrimeInspector.start(core);
        try {
          assertEquals(200, get(inspector.uri(), "/api/topology").status(), "round " + round);
        } finally {
          inspector.close();
        }
        assertEquals(Set.of(), inspectorThreads(), "threads left after close, round " + round);
      }
    }
  }

  @Test
  void closingEndsTheOpenStreamsAndLeavesNoThread() throws Exception {
    assertEquals(Set.of(), inspectorThreads(), "no inspector runs before the test");
    try (PrimeCore core = DemoController.declaredOn(new LibertyCore(recording()))) {
      core.start();
      PrimeInspector inspector = PrimeInspector.start(core);
      List<RawStream> streams = new ArrayList<>();
      try {
        for (int i = 0; i < 3; i++) {
          RawStream stream = new RawStream(inspector.uri(), i == 0 ? "/api/events" : "/api/events/odometry");
          streams.add(stream);
          stream.until("event: figures", 50);
        }
        assertTrue(inspectorThreads().size() >= 5, "a sampler, the dispatcher, 3 streams: " + inspectorThreads());
        long start = System.nanoTime();
        inspector.close();
        long closeMillis = (System.nanoTime() - start) / 1_000_000;
        assertTrue(closeMillis < 5_000, "close took " + closeMillis + " ms");
        // close returns only after every thread it made has ended: nothing to wait for here
        assertEquals(Set.of(), inspectorThreads(), "threads left after close");
        for (RawStream stream : streams) {
          // the stream ends: what is left of it is read, then the end (or a reset) comes
          int lines = 0;
          try {
            while (stream.line() != null) {
              assertTrue(++lines < 1_000, "the stream goes on after close");
            }
          } catch (java.net.SocketException reset) {
            // a connection closed under a pending write may be reset instead of ended
          }
        }
        inspector.close(); // twice does nothing
        assertThrows(IOException.class, () -> get(inspector.uri(), "/api/topology"));
      } finally {
        inspector.close();
        for (RawStream stream : streams) {
          stream.close();
        }
      }
    }
  }
}
