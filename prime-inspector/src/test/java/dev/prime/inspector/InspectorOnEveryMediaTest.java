package dev.prime.inspector;

import static dev.prime.inspector.InspectorHttpTest.get;
import static dev.prime.inspector.InspectorHttpTest.inspectorThreads;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.RecordingOptions;
import dev.prime.optimus.FaultProxy;
import dev.prime.optimus.OptimusCore;
import dev.prime.test.CoreSetup;
import dev.prime.test.Media;
import dev.prime.test.PrimeTest;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import java.util.Set;
import java.util.TreeMap;
import java.util.TreeSet;

/**
 * The page of a running core on each media: the diagram of its services, the figures of its
 * metrics (queue depths where the media has them: Optimus), the values it recorded; closing the
 * inspector ends its threads and leaves the core running. And on Optimus, the services another
 * process hosts are marked so the page draws them dashed. The Optimus runs again over a slow
 * Redis.
 */
class InspectorOnEveryMediaTest {
  private static final ObjectMapper JSON = new ObjectMapper();
  private static final Duration WAIT = Duration.ofSeconds(20);

  record Estimate(double x, double y) {}

  static class Watched implements CoreSetup {
    @Override
    public void configure(Media media, CoreConfig.Builder config) {
      config.metrics(true).recording(RecordingOptions.defaults());
    }
  }

  /** An Optimus core that hosts odometry only: the planner is another process's. */
  static final class HostsOdometryOnly extends Watched {
    @Override
    public PrimeCore optimus(CoreConfig config, String redisUrl) {
      return OptimusCore.builder().config(config).redis(redisUrl).hosts("odometry").build();
    }
  }

  /** Optimus on the class's Redis through a proxy that holds every reply back half a millisecond. */
  static final class WatchedOnSlowRedis extends Watched {
    @Override
    public PrimeCore optimus(CoreConfig config, String redisUrl) {
      return OptimusCore.builder().config(config).redis(FaultProxy.slowLinkTo(redisUrl)).build();
    }
  }

  /** {@link HostsOdometryOnly} on the slow Redis of {@link WatchedOnSlowRedis}. */
  static final class HostsOdometryOnlyOnSlowRedis extends Watched {
    @Override
    public PrimeCore optimus(CoreConfig config, String redisUrl) {
      return new HostsOdometryOnly().optimus(config, FaultProxy.slowLinkTo(redisUrl));
    }
  }

  private static Estimate odometry(Integer ticks) {
    return new Estimate(ticks * 0.5, -ticks);
  }

  /** The figures of the first posting that shows {@code node} with {@code total} values in. */
  private static JsonNode figuresWith(InspectorHttpTest.RawStream stream, String node, long total)
      throws Exception {
    JsonNode figures = null;
    // twice a second; 40 postings are 20 s
    for (int i = 0; i < 40; i++) {
      stream.until("event: figures", 50);
      figures = JSON.readTree(stream.until("data: ", 5).substring(6));
      if (figures.path("nodes").path(node).path("total").asLong() == total) {
        return figures;
      }
    }
    throw new AssertionError("no figures with " + total + " values into '" + node + "': " + figures);
  }

  @PrimeTest(media = Media.OPTIMUS, setup = WatchedOnSlowRedis.class)
  void showsTheDiagramFiguresAndValuesOfACoreOnASlowRedis(PrimeCore core, Media media)
      throws Exception {
    showsTheDiagramFiguresAndValuesOfACoreOnEveryMediaAndLeavesItRunning(core, media);
  }

  @PrimeTest(setup = Watched.class)
  void showsTheDiagramFiguresAndValuesOfACoreOnEveryMediaAndLeavesItRunning(
      PrimeCore core, Media media) throws Exception {
    EventBlock<Integer> encoders = new EventBlock<>();
    Reader<Estimate> estimates =
        core.source("encoders", encoders)
            .then(core.chain("odometry", InspectorOnEveryMediaTest::odometry))
            .reader();
    PrimeInspector inspector = PrimeInspector.start(core);
    try {
      core.start();
      for (int i = 1; i <= 5; i++) {
        encoders.publish(i);
      }
      for (int i = 1; i <= 5; i++) {
        assertEquals(odometry(i), estimates.take(WAIT).orElseThrow());
      }

      InspectorHttpTest.Answer topology = get(inspector.uri(), "/api/topology");
      assertEquals(200, topology.status(), topology.body());
      JsonNode layout = JSON.readTree(topology.body());
      assertEquals(core.name(), layout.get("core").asText());
      Set<String> drawn = new TreeSet<>();
      layout.get("nodes").forEach(node -> {
        drawn.add(node.get("name").asText());
        assertFalse(node.get("elsewhere").asBoolean(), "this process hosts " + node);
      });
      assertTrue(drawn.containsAll(core.serviceNames()), drawn + " holds " + core.serviceNames());

      InspectorHttpTest.Answer values = get(inspector.uri(), "/api/values/odometry");
      assertEquals(200, values.status(), values.body());
      List<Double> xs = new ArrayList<>();
      JSON.readTree(values.body()).get("points").forEach(p -> xs.add(p.get("fields").get("x").asDouble()));
      assertEquals(List.of(0.5, 1.0, 1.5, 2.0, 2.5), xs);

      try (InspectorHttpTest.RawStream stream = new InspectorHttpTest.RawStream(inspector.uri(), "/api/events")) {
        assertEquals("HTTP/1.1 200 OK", stream.line());
        JsonNode odometry = figuresWith(stream, "odometry", 5).get("nodes").get("odometry");
        assertEquals(0, odometry.get("errors").asLong(), odometry.toString());
        assertEquals(media == Media.OPTIMUS, odometry.get("queueDepth").isNumber(),
            "a queue depth where the media has a queue for the chain (Optimus): " + odometry);
        assertFalse(odometry.has("queueUnknown"), "a queue read, or none, is not unknown: " + odometry);
      }
    } finally {
      inspector.close();
    }
    assertEquals(Set.of(), inspectorThreads(), "threads left after close");
    assertFalse(core.isClosed(), "closing the inspector closed the core");
    encoders.publish(6);
    assertEquals(odometry(6), estimates.take(WAIT).orElseThrow(), "the core runs on");
  }

  @PrimeTest(media = Media.OPTIMUS, setup = HostsOdometryOnlyOnSlowRedis.class)
  void servicesAnotherProcessHostsAreMarkedToBeDrawnDashedOnASlowRedis(PrimeCore core)
      throws Exception {
    servicesAnotherProcessHostsAreMarkedToBeDrawnDashed(core);
  }

  @PrimeTest(media = Media.OPTIMUS, setup = HostsOdometryOnly.class)
  void servicesAnotherProcessHostsAreMarkedToBeDrawnDashed(PrimeCore core) throws Exception {
    EventBlock<Integer> encoders = new EventBlock<>();
    core.source("encoders", encoders)
        .then(core.chain("odometry", InspectorOnEveryMediaTest::odometry))
        .then(core.chain("planner", (Estimate e) -> new Estimate(1 - e.x(), 1 - e.y())));
    try (PrimeInspector inspector = PrimeInspector.start(core)) {
      core.start();
      InspectorHttpTest.Answer topology = get(inspector.uri(), "/api/topology");
      assertEquals(200, topology.status(), topology.body());
      Map<String, Boolean> elsewhere = new TreeMap<>();
      JSON.readTree(topology.body()).get("nodes").forEach(node -> {
        if (node.get("service").asBoolean()) {
          elsewhere.put(node.get("name").asText(), node.get("elsewhere").asBoolean());
        }
      });
      assertEquals(Map.of("odometry", false, "planner", true), elsewhere);
    }
  }
}
