package dev.prime.inspector.internal;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import java.io.IOException;
import java.io.InputStream;
import java.net.HttpURLConnection;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.URI;
import java.nio.charset.StandardCharsets;
import java.util.Map;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;

/**
 * A request whose answer fails unexpectedly (a RuntimeException or an Error other than a {@link
 * VirtualMachineError}, here from the figures' description, which the topology carries) is
 * answered 500 with a short plain body, and the inspector goes on serving.
 */
class HandlerFailureTest {
  record Answer(int status, String contentType, String body) {}

  static Answer get(URI uri, String path) throws IOException {
    HttpURLConnection connection = (HttpURLConnection) uri.resolve(path).toURL().openConnection();
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

  @Test
  void anAnswerThatFailsUnexpectedlyIsA500AndTheInspectorGoesOnServing() throws Exception {
    AtomicInteger described = new AtomicInteger();
    LiveFigures failing =
        new LiveFigures() {
          @Override
          public Map<String, NodeFigures> sample() {
            return Map.of();
          }

          @Override
          public String description() {
            return switch (described.incrementAndGet()) {
              case 1 -> throw new IllegalStateException("the figures are not ready");
              case 2 -> throw new NoClassDefFoundError("a figures class went missing");
              default -> "figures that fail twice";
            };
          }
        };
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().name("failing").build())) {
      InspectorServer server =
          new InspectorServer(
              core, failing, new InetSocketAddress(InetAddress.getLoopbackAddress(), 0));
      try {
        for (String thrown : new String[] {"IllegalStateException", "NoClassDefFoundError"}) {
          Answer failed = get(server.uri(), "/api/topology");
          assertEquals(500, failed.status(), failed.body());
          assertTrue(failed.contentType().startsWith("text/plain"), failed.contentType());
          assertTrue(failed.body().contains("/api/topology") && failed.body().contains(thrown),
              "the body says what failed: " + failed.body());
          assertTrue(failed.body().length() < 300, "a short body: " + failed.body());
        }
        Answer served = get(server.uri(), "/api/topology");
        assertEquals(200, served.status(), "served again after the failures: " + served.body());
        assertEquals(200, get(server.uri(), "/").status());
      } finally {
        server.close();
      }
    }
  }
}
