package dev.prime.faults;

import java.time.Duration;

/**
 * The network between the processes of a fault run and {@code redis-server}: {@link #DIRECT}, or
 * {@link #SLOW}, through a {@link FaultProxy} that holds every chunk back half a millisecond in
 * each direction, so every answer comes at least a millisecond late (the suite's counterpart of the
 * slow-Redis conformance variant). A fault that loses nothing on a fast network must lose nothing
 * when Redis answers late, too: more requests are in flight when the fault strikes.
 */
enum Network {
  DIRECT,
  SLOW;

  /** How long the slow network holds every chunk back, in each direction. */
  static final Duration SLOW_CHUNK_DELAY = Duration.ofNanos(500_000);

  /** For figure lines: nothing on the direct network, {@code " (slow network)"} on the slow one. */
  String suffix() {
    return this == DIRECT ? "" : " (slow network)";
  }

  /** Opens this network to {@code redis}; a restarted server on the same port is reached again. */
  Route open(RedisProcess redis) {
    if (this == DIRECT) return new Route(redis.url(), null);
    FaultProxy proxy = new FaultProxy(redis.port());
    proxy.delay(SLOW_CHUNK_DELAY);
    return new Route(proxy.url(), proxy);
  }

  /** One way to Redis: the URL every process of the run uses; closing it closes the proxy, if any. */
  static final class Route implements AutoCloseable {
    private final String url;
    private final FaultProxy proxy;

    private Route(String url, FaultProxy proxy) {
      this.url = url;
      this.proxy = proxy;
    }

    String url() {
      return url;
    }

    @Override
    public void close() {
      if (proxy != null) proxy.close();
    }
  }
}
