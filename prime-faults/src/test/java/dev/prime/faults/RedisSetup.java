package dev.prime.faults;

import dev.prime.optimus.LocalRedisCluster;
import java.time.Duration;
import redis.clients.jedis.Jedis;

/**
 * The Redis a fault run uses, one of the three set-ups Optimus runs on: {@link #DIRECT}, one
 * {@code redis-server} reached directly; {@link #SLOW_NETWORK}, the same through a
 * {@link FaultProxy} that holds every chunk back half a millisecond in each direction, so every
 * answer comes at least a millisecond late and more requests are in flight when a fault strikes
 * (the suite's counterpart of the slow-Redis conformance variant); and {@link #CLUSTER}, a real
 * Redis Cluster of 3 masters and 3 replicas ({@link LocalRedisCluster}). A fault that loses nothing
 * on one must lose nothing on the others.
 */
enum RedisSetup {
  DIRECT,
  SLOW_NETWORK,
  CLUSTER;

  /** How long the slow network holds every chunk back, in each direction. */
  static final Duration SLOW_CHUNK_DELAY = Duration.ofNanos(500_000);

  /** For figure lines: nothing for {@link #DIRECT}, else the set-up in parentheses. */
  String suffix() {
    switch (this) {
      case SLOW_NETWORK:
        return " (slow network)";
      case CLUSTER:
        return " (Redis Cluster)";
      default:
        return "";
    }
  }

  /** Starts a Redis of this set-up that keeps nothing on disk; closing it stops everything it started. */
  Redis start() {
    if (this == CLUSTER) {
      LocalRedisCluster cluster = LocalRedisCluster.start();
      return new Redis(cluster.getUrl(), null, null, cluster);
    }
    RedisProcess server = RedisProcess.start(RedisProcess.Persistence.NONE, null);
    try {
      Redis redis = through(server);
      return new Redis(redis.url, server, redis.proxy, null);
    } catch (RuntimeException e) {
      server.close();
      throw e;
    }
  }

  /**
   * The way to a server the test started itself, to crash and restart it (a restarted server on
   * the same port is reached again); closing it closes the proxy, if any, and leaves the server
   * to the test. Only for the set-ups of one server.
   */
  Redis through(RedisProcess server) {
    switch (this) {
      case DIRECT:
        return new Redis(server.url(), null, null, null);
      case SLOW_NETWORK:
        FaultProxy proxy = new FaultProxy(server.port());
        proxy.delay(SLOW_CHUNK_DELAY);
        return new Redis(proxy.url(), null, proxy, null);
      default:
        throw new IllegalArgumentException(this + " is not one redis-server: start() it instead");
    }
  }

  /** A running Redis of a set-up: the URL every process of the run uses, and a plain client for inspection. */
  static final class Redis implements AutoCloseable {
    private final String url;
    private final RedisProcess server; // owned; null if the test owns it, or for a cluster
    private final FaultProxy proxy; // null unless the network is slow
    private final LocalRedisCluster cluster; // null unless a cluster

    private Redis(String url, RedisProcess server, FaultProxy proxy, LocalRedisCluster cluster) {
      this.url = url;
      this.server = server;
      this.proxy = proxy;
      this.cluster = cluster;
    }

    String url() {
      return url;
    }

    /**
     * A new direct connection (the caller closes it) to the node that holds the keys of the
     * topology {@code coreName}: the one server, or the cluster master of the topology's slot.
     */
    Jedis clientFor(String coreName) {
      if (cluster != null) return cluster.masterOfKey(new TopologyKeys(coreName).codec()).jedis();
      if (server == null) throw new IllegalStateException("the test owns this server: use its own client()");
      return server.client();
    }

    @Override
    public void close() {
      try {
        if (proxy != null) proxy.close();
      } finally {
        if (server != null) server.close();
        if (cluster != null) cluster.close();
      }
    }
  }
}
