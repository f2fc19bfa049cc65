package dev.prime.inspector;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.inspector.internal.InspectorServer;
import dev.prime.inspector.internal.LiveFigures;
import dev.prime.inspector.internal.MetricsFigures;
import dev.prime.inspector.internal.NoFigures;
import dev.prime.inspector.internal.RecordingRates;
import java.io.UncheckedIOException;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.URI;
import java.util.Objects;

/**
 * A live diagram page for a running core, served by the JDK's HTTP server: the core's topology
 * drawn as a diagram (every service, template, source and reader, the links between them, the
 * services another process hosts drawn dashed), each node's live figures, and the latest values
 * of a chosen source or chain plotted over time, all updated by server-sent events twice a
 * second. The page is one HTML file with a small script and style sheet from this jar: it needs
 * no internet.
 *
 * <pre>{@code
 * try (PrimeCore core = new LibertyCore(CoreConfig.builder()
 *         .recording(RecordingOptions.defaults()).build());
 *     PrimeInspector inspector = PrimeInspector.start(core)) {
 *   ... declare, start ...
 *   System.out.println("watch it at " + inspector.uri());
 * }
 * }</pre>
 *
 * <p><b>Figures.</b> With metrics on ({@link CoreConfig.Builder#metrics(boolean)}), each metered
 * node (every chain that runs logic, template, filter, flat-map, listener and event source; see
 * {@link dev.prime.Metrics}) shows the values it took per second and in all, its mean processing
 * time over the last half second, its failures and, where the media has them, dead letters,
 * queue depth and missed values. A queue whose depth the media cannot read now (Optimus while
 * Redis is unreachable) shows as {@code queue ?}, not as no queue. With metrics off but recording
 * on ({@link CoreConfig.Builder#recording(RecordingOptions)}), each recorded source and chain shows
 * the values it recorded per second and in all. The page says which it shows.
 *
 * <p><b>Values.</b> With recording on, the values of a recorded name can be plotted: numbers,
 * booleans (0 or 1) and the numeric components of records (nested records as {@code pose.x}); a
 * NaN or an infinity (null in the JSON, which has neither) is left out of the plot. With recording
 * off the page says so and plots nothing.
 *
 * <p><b>Addresses.</b> {@code GET /} the page; {@code /api/topology} the layout as JSON; {@code
 * /api/events} the figures as server-sent events, {@code /api/events/NAME} the same with the
 * values recorded under {@code NAME}; {@code /api/values/NAME} the latest values of {@code NAME}
 * as JSON. A name that is not a node of the core, or not recorded, gets 404 with a message that
 * says why; a name of the core asked for with recording off gets 409. An answer that fails
 * unexpectedly (the core or the figures threw) gets 500 with a short plain body and is logged
 * with its stack trace ({@link System.Logger} {@code dev.prime.inspector.internal.InspectorServer});
 * the inspector goes on serving.
 *
 * <p><b>Threads.</b> One sampler thread and one thread per open page (at most 32), named {@code
 * prime-inspector-<core name>-...}, and the JDK server's dispatcher. {@link #close()} ends them
 * all, within a few seconds; it does not close the core. The inspector may outlive its core: the
 * page then shows it closed.
 *
 * <p><b>Security.</b> Anyone who reaches the address sees the diagram and the recorded values;
 * the page changes nothing. The default address is the loopback one.
 */
public final class PrimeInspector implements AutoCloseable {
  private final InspectorServer server;

  private PrimeInspector(InspectorServer server) {
    this.server = server;
  }

  /**
   * Serves a core's page on a free port of the loopback address ({@code 127.0.0.1}).
   *
   * @param core the core to show
   * @return the running inspector; close it when done
   * @throws UncheckedIOException if no port can be opened
   */
  public static PrimeInspector start(PrimeCore core) {
    return start(core, new InetSocketAddress(InetAddress.getLoopbackAddress(), 0));
  }

  /**
   * Serves a core's page on an address.
   *
   * @param core the core to show
   * @param address where to listen; port 0 picks a free port (see {@link #uri()})
   * @return the running inspector; close it when done
   * @throws UncheckedIOException if the address cannot be bound (a port in use, a port below 1024
   *     this process has no permission to bind, an address not of this machine, a host name not
   *     resolved); the message names the address, says which it is and what to give
   * @throws NullPointerException if an argument is null
   */
  public static PrimeInspector start(PrimeCore core, InetSocketAddress address) {
    Objects.requireNonNull(core, "core must not be null");
    Objects.requireNonNull(address, "address must not be null");
    LiveFigures figures;
    if (core.config().metrics()) {
      figures = new MetricsFigures(core.metrics());
    } else if (core.config().recording() != null) {
      figures = new RecordingRates(core.recording());
    } else {
      figures = new NoFigures();
    }
    return new PrimeInspector(new InspectorServer(core, figures, address));
  }

  /**
   * {@return the page's address, like {@code http://127.0.0.1:41234/}: the address it listens on,
   * with the port picked for port 0; for an inspector on the wildcard address (every interface:
   * {@code 0.0.0.0}, {@code ::}), which is no address to open, the loopback one ({@code
   * 127.0.0.1}, or {@code [::1]} for {@code ::}), where this machine reaches the page; other
   * machines reach it at an address of this machine with the same port}
   */
  public URI uri() {
    return server.uri();
  }

  /**
   * Stops serving: ends every event stream, the sampler and the server's threads, waiting for
   * them a few seconds at most; when it returns, every thread the inspector made has ended, unless
   * one outlasted that wait. The core is not closed. Closing twice does nothing.
   */
  @Override
  public void close() {
    server.close();
  }

  @Override
  public String toString() {
    return "PrimeInspector[" + server.uri() + "]";
  }
}
