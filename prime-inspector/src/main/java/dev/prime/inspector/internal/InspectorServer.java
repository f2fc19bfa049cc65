package dev.prime.inspector.internal;

import com.sun.net.httpserver.HttpExchange;
import com.sun.net.httpserver.HttpServer;
import dev.prime.PrimeCore;
import dev.prime.RecordedValue;
import dev.prime.Recording;
import dev.prime.topology.Topology;
import java.io.IOException;
import java.io.InputStream;
import java.io.OutputStream;
import java.io.UncheckedIOException;
import java.net.Inet6Address;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.NetworkInterface;
import java.net.SocketException;
import java.net.URI;
import java.net.URLDecoder;
import java.net.UnknownHostException;
import java.nio.charset.StandardCharsets;
import java.util.List;
import java.util.Locale;
import java.util.Map;
import java.util.Objects;
import java.util.Queue;
import java.util.Set;
import java.util.concurrent.ConcurrentLinkedQueue;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.ScheduledExecutorService;
import java.util.concurrent.Semaphore;
import java.util.concurrent.ThreadFactory;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;

/**
 * The inspector's HTTP server: the page, the topology as JSON, a chosen name's recorded values,
 * and the event streams.
 *
 * <p>Design note (threads). Three kinds of thread, all named {@code prime-inspector-<core>-...}
 * but the JDK server's own dispatcher: (1) one sampler, which every {@link #PERIOD_MILLIS} ms
 * takes the {@link LiveFigures} once and posts them to a {@link FigureBoard}; (2) the handler
 * pool of the JDK server, a cached pool: a plain request takes a thread for its answer only, an
 * event stream keeps its thread for as long as the browser listens, waiting on the board for the
 * next posting and then writing it (and, for a plotted name, the values recorded since it last
 * wrote). A browser that stops reading therefore stalls its own stream only. Open streams are
 * limited to {@link #MAX_STREAMS} (more get 503), so the pool is bounded too. (3) the JDK
 * server's dispatcher. {@link #close()} closes the board (waking every stream, which ends),
 * stops the sampler, stops the server (closing every connection, so a stream blocked in a write
 * fails and ends) and waits, bounded, for both pools to end and then for each of their threads
 * to end (a pool counts as ended when its last task returned, a moment before that task's thread
 * ends): every thread the server made is kept in {@link #made} until then.
 */
public final class InspectorServer implements AutoCloseable {
  /** How often the figures are sampled and sent, in milliseconds. */
  public static final long PERIOD_MILLIS = 500;
  /** The most event streams open at once. */
  static final int MAX_STREAMS = 32;
  /** The most values a stream sends at its start (the newest ones), and in one event. */
  static final int HISTORY = 300;
  private static final long CLOSE_WAIT_MILLIS = 5_000;
  private static final String EVENTS = "/api/events";
  private static final String VALUES = "/api/values/";
  private static final System.Logger LOG = System.getLogger(InspectorServer.class.getName());

  private final PrimeCore core;
  private final LiveFigures figures;
  private final Recording recording; // null: recording is off
  private final NumericFields numbers = new NumericFields();
  private final FigureBoard board = new FigureBoard();
  private final Semaphore streams = new Semaphore(MAX_STREAMS);
  private final Map<String, Page> pages;
  private final HttpServer server;
  private final ExecutorService handlers;
  private final ScheduledExecutorService sampler;
  /** Every thread the two pools made, for {@link #close()} to wait for. */
  private final Queue<Thread> made = new ConcurrentLinkedQueue<>();
  private final URI uri;
  private volatile boolean closed;

  private record Page(String contentType, byte[] bytes) {}

  /** Whether {@code address} is the wildcard, a loopback or an address of an interface here. */
  private static boolean isOfThisMachine(InetAddress address) {
    if (address.isAnyLocalAddress() || address.isLoopbackAddress()) {
      return true;
    }
    try {
      return NetworkInterface.getByInetAddress(address) != null;
    } catch (SocketException e) {
      return true; // the interfaces cannot be listed: make no claim about the address
    }
  }

  /**
   * Starts serving a core.
   *
   * @param core the core to show
   * @param figures where rates, latencies and errors come from
   * @param address where to listen
   * @throws UncheckedIOException if the address cannot be bound
   */
  public InspectorServer(PrimeCore core, LiveFigures figures, InetSocketAddress address) {
    this.core = Objects.requireNonNull(core, "core");
    this.figures = Objects.requireNonNull(figures, "figures");
    this.recording = core.config().recording() == null ? null : core.recording();
    this.pages =
        Map.of(
            "/", page("index.html", "text/html; charset=utf-8"),
            "/inspector.js", page("inspector.js", "text/javascript; charset=utf-8"),
            "/inspector.css", page("inspector.css", "text/css; charset=utf-8"));
    HttpServer bound;
    try {
      bound = HttpServer.create(address, 0);
    } catch (IOException e) {
      throw cannotListen(address, e);
    }
    this.server = bound;
    String prefix = "prime-inspector-" + core.name();
    this.handlers = Executors.newCachedThreadPool(threads(prefix + "-http-"));
    this.sampler = Executors.newSingleThreadScheduledExecutor(threads(prefix + "-sampler-"));
    server.setExecutor(handlers);
    server.createContext("/", this::handle);
    sampler.scheduleAtFixedRate(this::sample, 0, PERIOD_MILLIS, TimeUnit.MILLISECONDS);
    server.start();
    this.uri = uriOf(address, server.getAddress());
  }

  /**
   * {@return the page's address where the server listens on {@code local}, having been asked for
   * {@code asked}: on the wildcard address (every interface), which is no address to open, the
   * loopback one, 127.0.0.1, or [::1] where the IPv6 wildcard was asked for}
   */
  private static URI uriOf(InetSocketAddress asked, InetSocketAddress local) {
    InetAddress address = local.getAddress();
    if (address.isAnyLocalAddress() || asked.getAddress().isAnyLocalAddress()) {
      byte[] loopback = new byte[asked.getAddress() instanceof Inet6Address ? 16 : 4];
      if (loopback.length == 4) {
        loopback[0] = 127;
      }
      loopback[loopback.length - 1] = 1;
      try {
        address = InetAddress.getByAddress(loopback);
      } catch (UnknownHostException e) {
        throw new IllegalStateException("a loopback address of " + loopback.length + " bytes", e);
      }
    }
    String host = address.getHostAddress();
    if (host.contains(":")) {
      host = "[" + host + "]";
    }
    return URI.create("http://" + host + ":" + local.getPort() + "/");
  }

  /**
   * {@return the exception that says why the inspector cannot listen on {@code address}, which
   * refused with {@code e}, and what to give instead}
   */
  static UncheckedIOException cannotListen(InetSocketAddress address, IOException e) {
    String fix;
    if (address.isUnresolved()) {
      fix = "the host name '" + address.getHostString() + "' is not resolved; give an address of"
          + " this machine, like new InetSocketAddress(\"127.0.0.1\", " + address.getPort() + ")";
    } else if (!isOfThisMachine(address.getAddress())) {
      fix = address.getAddress().getHostAddress() + " is not an address of this machine; give one"
          + " of its addresses, like new InetSocketAddress(\"127.0.0.1\", " + address.getPort() + ")";
    } else if (isRefusal(e, "permission denied", "access denied", "eacces")) {
      fix = "no permission to listen on port " + address.getPort() + " of "
          + address.getAddress().getHostAddress() + ": ports below 1024 need a privilege on most"
          + " systems; give a port of 1024 or above (port 0 picks a free one), or let the JVM bind"
          + " low ports (on Linux, the CAP_NET_BIND_SERVICE capability)";
    } else if (isRefusal(e, "in use", "eaddrinuse")) {
      fix = "port " + address.getPort() + " of " + address.getAddress().getHostAddress()
          + " is in use by another program (or another inspector); stop it, or give another"
          + " port (port 0 picks a free one)";
    } else {
      fix = "give another port, or port 0, which picks a free one";
    }
    return new UncheckedIOException(
        "the inspector cannot listen on " + address + ": " + e.getMessage() + " (" + fix + ")", e);
  }

  /** Whether {@code e}'s message, the operating system's words, has one of {@code words}. */
  private static boolean isRefusal(IOException e, String... words) {
    String message = String.valueOf(e.getMessage()).toLowerCase(Locale.ROOT);
    for (String word : words) {
      if (message.contains(word)) {
        return true;
      }
    }
    return false;
  }

  /**
   * {@return the page's address: where the server listens, or the loopback address where it
   * listens on the wildcard address}
   */
  public URI uri() {
    return uri;
  }

  @Override
  public synchronized void close() {
    if (closed) {
      return;
    }
    closed = true;
    board.close();
    sampler.shutdownNow();
    server.stop(0);
    handlers.shutdownNow();
    long deadline = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(CLOSE_WAIT_MILLIS);
    try {
      sampler.awaitTermination(CLOSE_WAIT_MILLIS, TimeUnit.MILLISECONDS);
      handlers.awaitTermination(
          Math.max(0, deadline - System.nanoTime()), TimeUnit.NANOSECONDS);
      for (Thread thread : made) {
        long leftMillis = TimeUnit.NANOSECONDS.toMillis(deadline - System.nanoTime());
        if (leftMillis <= 0) {
          break;
        }
        thread.join(leftMillis);
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
  }

  private void sample() {
    String json;
    try {
      json = figuresJson(figures.sample());
    } catch (VirtualMachineError e) {
      throw e; // the JVM itself is in trouble
    } catch (Throwable e) {
      // Whatever else: a periodic task that throws is never run again, and every page would go
      // on showing its last figures as current. A media's gauges written in Kotlin may throw a
      // checked exception no signature declares, and an error may pass (a class gone missing).
      json = new Json().beginObject()
          .name("time").value(System.currentTimeMillis())
          .name("error").value("the figures could not be read: " + e)
          .name("nodes").beginObject().endObject()
          .endObject().toString();
    }
    board.post(json);
  }

  private String figuresJson(Map<String, NodeFigures> sampled) {
    Json json = new Json().beginObject();
    json.name("time").value(System.currentTimeMillis());
    json.name("started").value(core.isStarted()).name("closed").value(core.isClosed());
    Topology topology = core.topology();
    json.name("nodeCount").value(topology.nodes().size());
    // with the node count, what tells the page to lay the diagram out again (a standby taking a
    // service over)
    json.name("hostedElsewhere").strings(List.copyOf(topology.hostedElsewhere()));
    json.name("nodes").beginObject();
    for (Map.Entry<String, NodeFigures> entry : sampled.entrySet()) {
      NodeFigures f = entry.getValue();
      json.name(entry.getKey()).beginObject();
      json.name("rate").value(f.rate()).name("total").value(f.total());
      json.name("latencyMs").value(f.latencyMillis());
      count(json, "errors", f.errors());
      count(json, "deadLetters", f.deadLetters());
      count(json, "queueDepth", f.queueDepth());
      if (f.queueUnknown()) {
        json.name("queueUnknown").value(true);
      }
      count(json, "missed", f.missed());
      json.endObject();
    }
    return json.endObject().endObject().toString();
  }

  private static void count(Json json, String name, long count) {
    json.name(name);
    if (count >= 0) {
      json.value(count);
    } else {
      json.nullValue();
    }
  }

  private void handle(HttpExchange exchange) {
    try (exchange) {
      try {
        answer(exchange);
      } catch (VirtualMachineError e) {
        throw e; // the JVM itself is in trouble
      } catch (RuntimeException | Error e) {
        failed(exchange, e);
      }
    } catch (IOException e) {
      // the browser went away: nothing to answer
    }
  }

  private void answer(HttpExchange exchange) throws IOException {
    if (!exchange.getRequestMethod().equals("GET")) {
      exchange.getResponseHeaders().set("Allow", "GET");
      text(exchange, 405, "the inspector answers GET only, not " + exchange.getRequestMethod());
      return;
    }
    String path = exchange.getRequestURI().getRawPath();
    Page page = pages.get(path);
    if (page != null) {
      send(exchange, 200, page.contentType(), page.bytes());
    } else if (path.equals("/api/topology")) {
      send(exchange, 200, "application/json", topologyJson().getBytes(StandardCharsets.UTF_8));
    } else if (path.equals(EVENTS)) {
      stream(exchange, null);
    } else if (path.startsWith(EVENTS + "/")) {
      String name = decode(exchange, path.substring(EVENTS.length() + 1));
      if (name != null && plottable(exchange, name)) {
        stream(exchange, name);
      }
    } else if (path.startsWith(VALUES)) {
      String name = decode(exchange, path.substring(VALUES.length()));
      if (name != null && plottable(exchange, name)) {
        List<RecordedValue<Object>> values = recording.getAllStamped(name);
        String json = valuesJson(name, values.subList(Math.max(0, values.size() - HISTORY), values.size()));
        send(exchange, 200, "application/json", json.getBytes(StandardCharsets.UTF_8));
      }
    } else {
      text(exchange, 404,
          "the inspector has no page at " + path + "; it serves /, /api/topology, " + EVENTS
              + ", " + EVENTS + "/NAME and " + VALUES + "NAME (NAME a recorded source or chain)");
    }
  }

  /**
   * An answer failed unexpectedly (a bug, or a core or figures that threw): logs it and, if the
   * answer had not begun, answers 500 with a short plain body; the server goes on serving.
   */
  private void failed(HttpExchange exchange, Throwable e) {
    String what = exchange.getRequestMethod() + " " + exchange.getRequestURI().getRawPath();
    LOG.log(System.Logger.Level.WARNING,
        "the inspector of core '" + core.name() + "' could not answer " + what, e);
    if (exchange.getResponseCode() != -1) {
      return; // the answer had begun: closing the exchange ends it
    }
    try {
      text(exchange, 500, "the inspector could not answer " + what + ": "
          + e.getClass().getSimpleName() + " (its log has the details)");
    } catch (IOException | RuntimeException gone) {
      // the browser went away, or the exchange cannot answer any more: nothing more to do
    }
  }

  /** Whether {@code name} can be plotted; if not, answers with the reason and returns false. */
  private boolean plottable(HttpExchange exchange, String name) throws IOException {
    Topology topology = core.topology();
    if (topology.node(name).isEmpty()) {
      text(exchange, 404,
          "core '" + core.name() + "' has no service, source or chain named '" + name + "'; its"
              + " services: " + topology.services());
      return false;
    }
    if (recording == null) {
      text(exchange, 409,
          "core '" + core.name() + "' records nothing, so the values of '" + name + "' cannot be"
              + " plotted; create the core with CoreConfig.builder().recording("
              + "RecordingOptions.defaults())");
      return false;
    }
    Set<String> recorded = recording.names();
    if (!recorded.contains(name)) {
      text(exchange, 404,
          "'" + name + "' is not recorded (sources and chains made of a block are); recorded: "
              + recorded);
      return false;
    }
    return true;
  }

  private void stream(HttpExchange exchange, String plotted) throws IOException {
    if (!streams.tryAcquire()) {
      text(exchange, 503, "the inspector has " + MAX_STREAMS + " event streams open already;"
          + " close a page and reload");
      return;
    }
    try {
      exchange.getResponseHeaders().set("Content-Type", "text/event-stream; charset=utf-8");
      exchange.getResponseHeaders().set("Cache-Control", "no-store");
      exchange.sendResponseHeaders(200, 0);
      OutputStream body = exchange.getResponseBody();
      write(body, "retry: 1000\n\n");
      long seen = 0;
      long next = plotted == null ? 0 : Math.max(0, recording.recorded(plotted) - HISTORY);
      while (!closed) {
        FigureBoard.Posting posting = board.awaitAfter(seen, 2 * PERIOD_MILLIS);
        if (closed) {
          break;
        }
        StringBuilder event = new StringBuilder();
        if (posting != null) {
          seen = posting.generation();
          event.append("event: figures\ndata: ").append(posting.json()).append("\n\n");
        }
        if (plotted != null) {
          final long from = next;
          List<RecordedValue<Object>> values = recording.getRangeStamped(plotted, from, Long.MAX_VALUE);
          if (!values.isEmpty()) {
            next = values.get(values.size() - 1).sequence() + 1;
            values = values.subList(Math.max(0, values.size() - HISTORY), values.size());
            event.append("event: values\ndata: ").append(valuesJson(plotted, values)).append("\n\n");
          }
        }
        write(body, event.length() == 0 ? ": waiting\n\n" : event.toString());
      }
    } catch (InterruptedException e) {
      // the inspector is closing
    } finally {
      streams.release();
    }
  }

  private String valuesJson(String name, List<RecordedValue<Object>> values) {
    Json json = new Json().beginObject().name("service").value(name);
    json.name("dropped").value(recording.dropped(name));
    json.name("points").beginArray();
    for (RecordedValue<Object> value : values) {
      json.beginObject()
          .name("seq").value(value.sequence())
          .name("t").value(value.wallTime().toEpochMilli())
          .name("fields").numbers(numbers.of(value.value()))
          .endObject();
    }
    return json.endArray().endObject().toString();
  }

  private String topologyJson() {
    Topology topology = core.topology();
    Json json = new Json().beginObject();
    json.name("core").value(core.name());
    json.name("media").value(core.getClass().getSimpleName());
    json.name("recording").value(recording != null);
    json.name("recorded").strings(recording == null ? List.of() : List.copyOf(recording.names()));
    json.name("services").strings(List.copyOf(topology.services()));
    json.name("figures").value(figures.description());
    json.name("period").value(PERIOD_MILLIS);
    json.name("nodeCount").value(topology.nodes().size()); // links too, as in the figures
    json.name("hostedElsewhere").strings(List.copyOf(topology.hostedElsewhere()));
    DiagramLayout.of(topology).write(json);
    return json.endObject().toString();
  }

  private static String decode(HttpExchange exchange, String raw) throws IOException {
    try {
      return URLDecoder.decode(raw.replace("+", "%2B"), StandardCharsets.UTF_8);
    } catch (IllegalArgumentException e) {
      text(exchange, 400, "'" + raw + "' is not a well-formed name in a URL: " + e.getMessage());
      return null;
    }
  }

  private static void write(OutputStream body, String text) throws IOException {
    body.write(text.getBytes(StandardCharsets.UTF_8));
    body.flush();
  }

  private static void text(HttpExchange exchange, int status, String message) throws IOException {
    send(exchange, status, "text/plain; charset=utf-8",
        (message + "\n").getBytes(StandardCharsets.UTF_8));
  }

  private static void send(HttpExchange exchange, int status, String type, byte[] bytes)
      throws IOException {
    exchange.getResponseHeaders().set("Content-Type", type);
    exchange.getResponseHeaders().set("Cache-Control", "no-store");
    exchange.sendResponseHeaders(status, bytes.length);
    try (OutputStream body = exchange.getResponseBody()) {
      body.write(bytes);
    }
  }

  private static Page page(String file, String contentType) {
    try (InputStream in = InspectorServer.class.getResourceAsStream("/dev/prime/inspector/page/" + file)) {
      if (in == null) {
        throw new IllegalStateException("the inspector's page " + file + " is missing from its jar");
      }
      return new Page(contentType, in.readAllBytes());
    } catch (IOException e) {
      throw new UncheckedIOException("cannot read the inspector's page " + file, e);
    }
  }

  private ThreadFactory threads(String prefix) {
    AtomicInteger count = new AtomicInteger();
    return runnable -> {
      Thread thread = new Thread(runnable, prefix + count.incrementAndGet());
      thread.setDaemon(true);
      made.removeIf(old -> old.getState() == Thread.State.TERMINATED); // a cached pool's idle threads end
      made.add(thread);
      return thread;
    };
  }
}
