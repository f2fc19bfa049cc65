package dev.prime.inspector.internal;

import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeTrue;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import java.io.IOException;
import java.io.UncheckedIOException;
import java.net.BindException;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.ServerSocket;
import org.junit.jupiter.api.Test;

/**
 * An address the inspector cannot listen on is refused with what happened (the port in use, or
 * no permission to bind it) and how to fix it.
 */
class ListenRefusalTest {
  private static final InetAddress LOOPBACK = InetAddress.getLoopbackAddress();

  @Test
  void aPortInUseIsSaidToBeInUseWithWhatToDo() throws Exception {
    try (ServerSocket holder = new ServerSocket(0, 1, LOOPBACK);
        PrimeCore core = new LibertyCore(CoreConfig.builder().name("refused").build())) {
      InetSocketAddress taken = new InetSocketAddress(LOOPBACK, holder.getLocalPort());
      UncheckedIOException refused =
          assertThrows(
              UncheckedIOException.class, () -> new InspectorServer(core, new NoFigures(), taken));
      String message = refused.getMessage();
      assertTrue(message.contains("port " + taken.getPort() + " of " + LOOPBACK.getHostAddress()
          + " is in use by another program"), message);
      assertTrue(message.contains("port 0 picks a free one"), message);
      assertFalse(message.contains("?"), "says what happened, asks nothing: " + message);
    }
  }

  /** The refusal the JDK throws where binding a port below 1024 needs a privilege. */
  @Test
  void aPermissionRefusalIsSaidToBeOneWithWhatToDo() {
    InetSocketAddress low = new InetSocketAddress(LOOPBACK, 80);
    String message =
        InspectorServer.cannotListen(low, new BindException("Permission denied")).getMessage();
    assertPermissionRefusal(message, 80);
  }

  /**
   * The same from a real bind, where this process may not bind low ports (not root, no
   * CAP_NET_BIND_SERVICE); skipped where it may.
   */
  @Test
  void aLowPortThisProcessMayNotBindIsSaidToNeedAPermission() throws Exception {
    int port = 1;
    boolean mayBind;
    try (ServerSocket probe = new ServerSocket(port, 1, LOOPBACK)) {
      mayBind = probe.isBound();
    } catch (BindException refused) {
      mayBind = !String.valueOf(refused.getMessage()).contains("Permission denied");
    } catch (IOException other) {
      mayBind = true;
    }
    assumeTrue(!mayBind, "this process may bind port " + port + " (root or CAP_NET_BIND_SERVICE)");
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().name("refused").build())) {
      UncheckedIOException refused =
          assertThrows(
              UncheckedIOException.class,
              () -> new InspectorServer(core, new NoFigures(), new InetSocketAddress(LOOPBACK, port)));
      assertPermissionRefusal(refused.getMessage(), port);
    }
  }

  private static void assertPermissionRefusal(String message, int port) {
    assertTrue(message.contains("no permission to listen on port " + port), message);
    assertTrue(message.contains("port 0 picks a free one"), message);
    assertTrue(message.contains("CAP_NET_BIND_SERVICE"), message);
    assertFalse(message.contains("taken"), "the port is not taken: " + message);
  }
}
