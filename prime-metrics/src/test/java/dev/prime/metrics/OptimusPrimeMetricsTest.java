package dev.prime.metrics;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.FaultProxy;
import dev.prime.optimus.Hosting;
import dev.prime.optimus.OptimusCore;
import io.micrometer.core.instrument.Gauge;
import io.micrometer.core.instrument.simple.SimpleMeterRegistry;
import java.time.Duration;
import org.junit.jupiter.api.Test;

/** The binder on Optimus, each core on an embedded Redis of its own (a real redis-server). */
class OptimusPrimeMetricsTest extends PrimeMetricsContract {
  @Override
  PrimeCore newCore(CoreConfig config) {
    return OptimusCore.builder().config(config).build();
  }

  @Override
  String media() {
    return "optimus";
  }

  @Override
  boolean deadLetters() {
    return true;
  }

  @Override
  boolean chainsHaveQueues() {
    return true;
  }

  /** The dead-letter gauge reads the service's dead letters, so clearing them lowers it. */
  @Test
  void clearingAServicesDeadLettersLowersItsGauge() throws Exception {
    CoreConfig config =
        CoreConfig.builder().metrics(true).errorHandler((service, input, error) -> {}).build();
    try (OptimusCore core = (OptimusCore) newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> passed =
          core.source("numbers", events)
              .then(
                  core.chain(
                      "picky",
                      (Integer x) -> {
                        if (x < 0) {
                          throw new IllegalArgumentException("negative: " + x);
                        }
                        return x;
                      }))
              .reader();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      core.start();
      events.publish(-1);
      events.publish(-2);
      events.publish(3);
      assertEquals(3, take(passed)); // the two before it are dead letters by now
      Gauge deadLetters = registry.get(PrimeMetrics.DEAD_LETTERS).tag("service", "picky").gauge();
      assertEquals(2, deadLetters.value());
      assertEquals(2, core.clearDeadLetters("picky"));
      assertEquals(0, deadLetters.value());
    }
  }

  /**
   * A service's queue-depth gauge is registered when the binder binds while Redis is unreachable
   * (it reads NaN then), and reads the queue once Redis answers again.
   */
  @Test
  void aQueueBoundWhileRedisIsUnreachableGetsItsGaugeWhichReadsOnceRedisIsBack() throws Exception {
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        FaultProxy proxy = new FaultProxy(redis.getUri());
        OptimusCore core =
            OptimusCore.builder()
                .config(CoreConfig.builder().metrics(true).build())
                .redis(proxy.getUrl())
                .build()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out = core.source("numbers", events).then(core.chain("same", (Integer x) -> x)).reader();
      core.start();
      proxy.refuse();
      assertEquals(-1, core.metrics().service("same").queueDepth(), "Redis cannot be read now");
      assertTrue(core.metrics().hasQueue("same"));
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      Gauge depth = registry.find(PrimeMetrics.QUEUE_DEPTH).tag("service", "same").gauge();
      assertNotNull(depth, "a queue-depth gauge for the service, bound while Redis was down");
      assertEquals(Double.NaN, depth.value());

      proxy.restore();
      events.publish(5);
      assertEquals(5, take(out));
      // Redis answers (the value went through); the gauges' own connection was cut, so their
      // first read may fail (NaN) and drop it, and the next one connects anew
      double read = depth.value();
      for (int i = 0; i < 3 && Double.isNaN(read); i++) {
        read = depth.value();
      }
      assertEquals(0, read, "the gauge reads the queue once Redis answers");
    }
  }

  /**
   * The gauges read NaN while Optimus cannot read the numbers from Redis, as after the core
   * closed (the queue-depth gauge exists from binding, when they could be read).
   */
  @Test
  void theGaugesReadNanWhileRedisCannotBeRead() throws Exception {
    PrimeCore core = newCore(CoreConfig.builder().metrics(true).build());
    try (core) {
      core.chain("same", (Integer x) -> x);
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      core.start();
      assertEquals(0, registry.get(PrimeMetrics.QUEUE_DEPTH).tag("service", "same").gauge().value());
      core.close();
      assertEquals(
          Double.NaN, registry.get(PrimeMetrics.QUEUE_DEPTH).tag("service", "same").gauge().value());
      assertEquals(
          Double.NaN, registry.get(PrimeMetrics.DEAD_LETTERS).tag("service", "same").gauge().value());
    }
  }

  /**
   * While another process runs a service this core hosts too (a standby of a {@link
   * Hosting#ORDERED} one), the service is not metered here: its meters read NaN, and reading them
   * takes no snapshot of its own, so the other meters are still served from the snapshot of the
   * refresh period, as a registry reading every meter expects (on Optimus a snapshot asks Redis
   * about every service).
   */
  @Test
  void theMetersOfAServiceAnotherProcessRunsAreServedFromTheSnapshotToo() throws Exception {
    CoreConfig config = CoreConfig.builder().name("standby").metrics(true).build();
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        OptimusCore active =
            OptimusCore.builder().config(config).redis(redis.getUri())
                .hosts("ordered").hosting("ordered", Hosting.ORDERED).build();
        OptimusCore standby =
            OptimusCore.builder().config(config).redis(redis.getUri())
                .hosting("ordered", Hosting.ORDERED).build()) {
      Block<Integer, Integer> orderedOnActive = active.chain("ordered", (Integer x) -> x).toBlock();
      active.chain("same", (Integer x) -> x).toBlock();
      standby.chain("ordered", (Integer x) -> x).toBlock();
      Block<Integer, Integer> same = standby.chain("same", (Integer x) -> x).toBlock();
      active.start();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(standby, Duration.ofHours(1)).bindTo(registry);
      standby.start();
      assertEquals(1, orderedOnActive.process(1), "the active process runs the ordered service");
      assertFalse(standby.metrics().names().contains("ordered"), "not metered by the standby");

      assertEquals(0, count(registry, PrimeMetrics.VALUES_IN, "same")); // the snapshot is taken
      assertEquals(7, same.process(7));
      assertEquals(Double.NaN, count(registry, PrimeMetrics.VALUES_IN, "ordered"));
      assertEquals(Double.NaN,
          registry.get(PrimeMetrics.QUEUE_DEPTH).tag("service", "ordered").gauge().value());
      assertEquals(0, count(registry, PrimeMetrics.VALUES_IN, "same"),
          "served from the snapshot, also after reading the meters of the standby's service");
    }
  }

  /**
   * Bound once the core runs, as the README binds it ({@code whenRunning}), a standby's binder
   * gives the service it stands by for its meters once it has taken the service over from the
   * process that ran it: they count and time what it processes here.
   */
  @Test
  void aServiceTakenOverAfterBindingGetsItsMeters() throws Exception {
    CoreConfig config = CoreConfig.builder().name("takeover").metrics(true).build();
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        OptimusCore standby =
            OptimusCore.builder().config(config).redis(redis.getUri())
                .leaseTime(Duration.ofSeconds(1)).hosting("ordered", Hosting.ORDERED).build()) {
      OptimusCore active =
          OptimusCore.builder().config(config).redis(redis.getUri())
              .leaseTime(Duration.ofSeconds(1)).hosts("ordered").hosting("ordered", Hosting.ORDERED)
              .build();
      try {
        active.chain("ordered", (Integer x) -> x).toBlock();
        Block<Integer, Integer> ordered = standby.chain("ordered", (Integer x) -> x).toBlock();
        Block<Integer, Integer> same = standby.chain("same", (Integer x) -> x).toBlock();
        SimpleMeterRegistry registry = new SimpleMeterRegistry();
        PrimeMetrics binder = PrimeMetrics.of(standby, Duration.ZERO);
        active.start();
        standby.whenRunning("metrics", () -> binder.bindTo(registry), binder::close);
        standby.start();
        assertNull(registry.find(PrimeMetrics.VALUES_IN).tag("service", "ordered").functionCounter(),
            "no meters while the active process runs it");

        active.close();
        long deadline = System.nanoTime() + PATIENCE.toNanos();
        while (!standby.serviceNames().contains("ordered") && System.nanoTime() < deadline) {
          Thread.sleep(10); // polling the core, bounded by the deadline
        }
        assertTrue(standby.serviceNames().contains("ordered"), "the standby took 'ordered' over");
        assertEquals(5, ordered.process(5));
        assertEquals(1, same.process(1));
        assertEquals(1, count(registry, PrimeMetrics.VALUES_IN, "same")); // a read of the meters
        assertNotNull(registry.find(PrimeMetrics.VALUES_IN).tag("service", "ordered").functionCounter(),
            "the meters of the service the standby took over");
        assertEquals(6, ordered.process(6));
        assertEquals(standby.metrics().service("ordered").valuesIn(),
            count(registry, PrimeMetrics.VALUES_IN, "ordered"));
        assertEquals(1, registry.get(PrimeMetrics.PROCESSING).tag("service", "ordered").timer().count(),
            "the value processed after its meters came, timed");
      } finally {
        active.close();
      }
    }
  }
}
