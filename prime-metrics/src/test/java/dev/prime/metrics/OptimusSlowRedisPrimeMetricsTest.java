package dev.prime.metrics;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.FaultProxy;
import dev.prime.optimus.OptimusCore;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.AfterEach;

/**
 * The binder on Optimus over a slow network: each core on a redis-server of its own, reached
 * through a proxy that holds every reply back half a millisecond, as the slow-Redis variant of the
 * conformance kit does. Every test of the contract, and the Optimus ones, run here too.
 */
class OptimusSlowRedisPrimeMetricsTest extends OptimusPrimeMetricsTest {
  private final List<AutoCloseable> redisOfCores = new ArrayList<>();

  @Override
  PrimeCore newCore(CoreConfig config) {
    EmbeddedRedis redis = EmbeddedRedis.start();
    FaultProxy proxy = new FaultProxy(redis.getUri(), FaultProxy.SLOW_REPLY_NANOS);
    redisOfCores.add(redis);
    redisOfCores.add(proxy);
    return OptimusCore.builder().config(config).redis(proxy.getUrl()).build();
  }

  /** After the test closed its cores: the proxies, then their servers. */
  @AfterEach
  void closeTheServers() throws Exception {
    for (int i = redisOfCores.size() - 1; i >= 0; i--) {
      redisOfCores.get(i).close();
    }
    redisOfCores.clear();
  }
}
