package dev.prime.faults;

import dev.prime.optimus.EmbeddedRedis;
import java.io.IOException;
import java.io.UncheckedIOException;
import java.net.ServerSocket;
import java.net.InetAddress;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;
import redis.clients.jedis.DefaultJedisClientConfig;
import redis.clients.jedis.HostAndPort;
import redis.clients.jedis.Jedis;

/**
 * A redis-server process a fault test controls: started on a loopback port with the chosen
 * persistence, killed with SIGKILL (a crash) or SIGTERM, and restarted on the same port with its
 * data or empty.
 *
 * <p>Design note. Servers are launched through prime-optimus' public {@link EmbeddedRedis}, so the
 * suite runs the very binary and flags the project resolves (AOF with {@code appendfsync always}
 * when persistent). The process is signalled through its {@link ProcessHandle}, found by the pid
 * the server reports in {@code INFO}, so no option of {@code EmbeddedRedis} is needed for a crash.
 * A restart launches a new server on the same port: with the same append-only directory (the data
 * kept) or with a fresh one (the data lost). Not thread-safe: one test drives it. {@link #close()}
 * stops every server it started.
 */
final class RedisProcess implements AutoCloseable {
  /** What the server keeps on disk. */
  enum Persistence { NONE, AOF_ALWAYS }

  private final Persistence persistence;
  private final Path dir;
  private final int port;
  private final List<EmbeddedRedis> servers = new ArrayList<>();
  private EmbeddedRedis current;
  private int generation;

  private RedisProcess(Persistence persistence, Path dir, int port) {
    this.persistence = persistence;
    this.dir = dir;
    this.port = port;
  }

  /** Starts a server on a free loopback port; {@code dir} holds its append-only files if persistent. */
  static RedisProcess start(Persistence persistence, Path dir) {
    RedisProcess redis = new RedisProcess(persistence, dir, freePort());
    redis.launch(true);
    return redis;
  }

  int port() {
    return port;
  }

  /** {@code redis://127.0.0.1:<port>}. */
  String url() {
    return "redis://127.0.0.1:" + port;
  }

  /** The pid of the running server. */
  long pid() {
    try (Jedis jedis = client()) {
      for (String line : jedis.info("server").split("\r?\n")) {
        if (line.startsWith("process_id:")) return Long.parseLong(line.substring("process_id:".length()).trim());
      }
    }
    throw new IllegalStateException("redis-server on port " + port + " reports no process_id");
  }

  /** A new connection (the caller closes it), with a 10 s timeout. */
  Jedis client() {
    return new Jedis(new HostAndPort("127.0.0.1", port),
        DefaultJedisClientConfig.builder().resp2().autoNegotiateProtocol(false).timeoutMillis(10_000).build());
  }

  /** Kills the server with SIGKILL, as a crash would, and waits until it is gone. */
  void kill() {
    signal(true);
  }

  /** Stops the server with SIGTERM (it may save) and waits until it is gone. */
  void terminate() {
    signal(false);
  }

  /** Starts a server again on the same port: with its data ({@code keepData}) or empty. */
  void restart(boolean keepData) {
    launch(keepData);
  }

  @Override
  public void close() {
    for (EmbeddedRedis server : servers) server.close();
    servers.clear();
  }

  private void signal(boolean forcibly) {
    ProcessHandle process = ProcessHandle.of(pid())
        .orElseThrow(() -> new IllegalStateException("redis-server on port " + port + " is not running"));
    if (forcibly) process.destroyForcibly(); else process.destroy();
    try {
      process.onExit().get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new IllegalStateException("interrupted while stopping redis-server", e);
    } catch (ExecutionException | TimeoutException e) {
      throw new IllegalStateException("redis-server pid " + process.pid() + " did not stop", e);
    }
  }

  private void launch(boolean keepData) {
    EmbeddedRedis.Builder builder = EmbeddedRedis.builder().port(port);
    if (persistence == Persistence.AOF_ALWAYS) {
      if (!keepData) generation++;
      Path data = dir.resolve("data-" + generation);
      try {
        Files.createDirectories(data);
      } catch (IOException e) {
        throw new UncheckedIOException(e);
      }
      builder.appendOnlyDir(data);
    }
    current = builder.start();
    servers.add(current);
  }

  private static int freePort() {
    try (ServerSocket socket = new ServerSocket(0, 1, InetAddress.getLoopbackAddress())) {
      return socket.getLocalPort();
    } catch (IOException e) {
      throw new UncheckedIOException(e);
    }
  }

  @Override
  public String toString() {
    return "RedisProcess[" + url() + ", " + persistence + ", " + (current != null && current.isRunning() ? "running" : "stopped") + "]";
  }
}
