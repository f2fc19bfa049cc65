package dev.prime.test.internal;

import java.io.IOException;
import java.io.UncheckedIOException;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.StandardSocketOptions;
import java.net.URI;
import java.net.URISyntaxException;
import java.nio.ByteBuffer;
import java.nio.channels.CancelledKeyException;
import java.nio.channels.Channel;
import java.nio.channels.SelectionKey;
import java.nio.channels.Selector;
import java.nio.channels.ServerSocketChannel;
import java.nio.channels.SocketChannel;
import java.time.Duration;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.concurrent.locks.LockSupport;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.extension.ExtensionConfigurationException;
import org.junit.jupiter.api.extension.ExtensionContext;

/**
 * A TCP proxy on the loopback interface in front of one Redis that delays every byte it forwards,
 * in each direction, by a fixed time: the slow network link of {@code OPTIMUS_SLOW_LINK} runs.
 * Each byte the core sends reaches Redis {@code delay} after the proxy read it, and each byte of
 * Redis's answer reaches the core {@code delay} after the proxy read it, so every round trip
 * takes twice the delay longer. Bytes read together arrive together (the delay is a latency, the
 * bandwidth is not limited), and connecting costs no delay of its own.
 *
 * <p>Design note: one daemon thread, {@code prime-test-slow-link-<port>}, runs a selector over the
 * listening socket and the two sockets of every connection. Each chunk it reads is stamped with
 * the time it is due (read time plus the delay) and queued for the other side; the thread writes
 * it once due, waiting in {@code select} (or parked, for the last millisecond) until the next due
 * chunk, so no connection waits for another and no chunk leaves early. Once {@value #QUEUE_LIMIT}
 * bytes wait in a direction of a connection, its source is not read until they drain, and TCP's
 * flow control slows the sender, so memory stays bounded (reads are {@value #READ_SIZE} bytes at
 * most). All state but the {@code closed} and {@code failure} fields is the thread's own; {@link
 * #close()} sets the flag, wakes the selector and waits for the thread, which closes every socket
 * as it ends.
 *
 * <p>Kept in the test class's extension store, it is a {@link
 * ExtensionContext.Store.CloseableResource} as well as an {@link AutoCloseable}, so that every
 * JUnit 5 closes it after the class (JUnit closes an {@code AutoCloseable} only from 5.13 on), and
 * closed once.
 */
@SuppressWarnings("deprecation") // CloseableResource: how JUnit before 5.13 closes a store's value
final class SlowLink implements AutoCloseable, ExtensionContext.Store.CloseableResource {

  /** The JUnit configuration parameter of the delay. */
  static final String DELAY_PARAMETER = "prime.test.slowLink.delay";

  /** The delay each way unless {@link #DELAY_PARAMETER} says otherwise. */
  static final Duration DEFAULT_DELAY = Duration.ofMillis(1);

  /** The longest delay accepted. */
  static final Duration MAX_DELAY = Duration.ofSeconds(10);

  /** The name of every proxy thread starts with this. */
  static final String THREAD_PREFIX = "prime-test-slow-link-";

  private static final int QUEUE_LIMIT = 256 * 1024;
  private static final int READ_SIZE = 16 * 1024;
  private static final long JOIN_MILLIS = 5_000;
  private static final long ONE_MILLI = TimeUnit.MILLISECONDS.toNanos(1);
  private static final Pattern DELAY = Pattern.compile("(\\d{1,5})(?:\\.(\\d{1,6}))?\\s*ms");

  private final String url;
  private final long delayNanos;
  private final InetSocketAddress target;
  private final ServerSocketChannel server;
  private final Selector selector;
  private final Thread thread;
  private final List<Connection> connections = new ArrayList<>(); // the thread's own
  private final ByteBuffer readBuffer = ByteBuffer.allocate(READ_SIZE); // the thread's own
  private volatile boolean closed;
  private final AtomicBoolean closeCalled = new AtomicBoolean();
  private volatile Throwable failure;

  private SlowLink(URI redis, Duration delay) throws IOException {
    this.delayNanos = delay.toNanos();
    this.target = new InetSocketAddress(redis.getHost(), redis.getPort() < 0 ? 6379 : redis.getPort());
    this.selector = Selector.open();
    ServerSocketChannel listening = null;
    try {
      listening = ServerSocketChannel.open();
      listening.bind(new InetSocketAddress(InetAddress.getLoopbackAddress(), 0));
      listening.configureBlocking(false);
      listening.register(selector, SelectionKey.OP_ACCEPT);
    } catch (IOException | RuntimeException e) {
      if (listening != null) {
        listening.close();
      }
      selector.close();
      throw e;
    }
    this.server = listening;
    InetSocketAddress local = (InetSocketAddress) server.getLocalAddress();
    this.url = proxiedUrl(redis, local);
    this.thread = new Thread(this::run, THREAD_PREFIX + local.getPort());
    thread.setDaemon(true);
    thread.start();
  }

  /**
   * Opens a proxy in front of the Redis at {@code redisUrl}.
   *
   * @param redisUrl a {@code redis://} URL of one server
   * @param delay how long each byte is held back, each way
   * @return the running proxy
   * @throws ExtensionConfigurationException if the URL is not that of one server without TLS
   * @throws UncheckedIOException if the proxy cannot listen
   */
  static SlowLink open(String redisUrl, Duration delay) {
    URI redis = redisUri(redisUrl);
    try {
      return new SlowLink(redis, delay);
    } catch (IOException e) {
      throw new UncheckedIOException("the slow link to " + redisUrl + " cannot listen on the"
          + " loopback interface: " + e.getMessage(), e);
    }
  }

  /**
   * Reads the delay of {@link #DELAY_PARAMETER}: milliseconds followed by {@code ms}, with up to
   * six decimals ({@code 2ms}, {@code 0.5ms}), from {@code 0ms} to {@code 10000ms}.
   *
   * @param value the parameter's value, or {@code null} if it is not set
   * @return the delay each way
   * @throws ExtensionConfigurationException if the value is not such a delay
   */
  static Duration parseDelay(String value) {
    if (value == null) {
      return DEFAULT_DELAY;
    }
    Matcher m = DELAY.matcher(value.trim().toLowerCase(Locale.ROOT));
    Duration delay = null;
    if (m.matches()) {
      String fraction = m.group(2) == null ? "" : m.group(2);
      long nanos = Long.parseLong((fraction + "000000").substring(0, 6));
      delay = Duration.ofMillis(Long.parseLong(m.group(1))).plusNanos(nanos);
    }
    if (delay == null || delay.compareTo(MAX_DELAY) > 0) {
      throw new ExtensionConfigurationException(
          "the JUnit configuration parameter " + DELAY_PARAMETER + " is '" + value + "', which is"
              + " not a delay of the slow link: give milliseconds followed by ms, from 0ms to"
              + " 10000ms, like " + DELAY_PARAMETER + "=2ms or " + DELAY_PARAMETER + "=0.5ms"
              + " (how long each byte takes each way; unset, 1ms)");
    }
    return delay;
  }

  /** {@return the URL of the Redis through this proxy: the Redis's, on the proxy's address} */
  String url() {
    return url;
  }

  /**
   * Stops the proxy: closes the listening socket and every connection, and waits for its thread
   * to end. Only the first call does anything.
   *
   * @throws IllegalStateException if the thread has not ended within 5 s, or if it failed
   *     while the proxy ran (the selector threw)
   */
  @Override
  public void close() {
    if (!closeCalled.compareAndSet(false, true)) {
      return;
    }
    closed = true;
    selector.wakeup();
    try {
      thread.join(JOIN_MILLIS);
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
    if (thread.isAlive()) {
      throw new IllegalStateException(
          "the slow link's thread " + thread.getName() + " did not end within " + JOIN_MILLIS
              + " ms of close()");
    }
    if (failure != null) {
      throw new IllegalStateException(
          "the slow link's thread " + thread.getName() + " failed, which dropped every connection"
              + " through it: " + failure, failure);
    }
  }

  private static URI redisUri(String redisUrl) {
    URI redis;
    try {
      redis = new URI(redisUrl);
    } catch (URISyntaxException e) {
      throw new ExtensionConfigurationException(
          "OPTIMUS_SLOW_LINK cannot front the Redis at '" + redisUrl + "': it is not a URL ("
              + e.getMessage() + "); give redis://host:port", e);
    }
    String scheme = redis.getScheme() == null ? "" : redis.getScheme().toLowerCase(Locale.ROOT);
    if (scheme.equals("redis-cluster") || scheme.equals("rediss-cluster")) {
      throw new ExtensionConfigurationException(
          "OPTIMUS_SLOW_LINK cannot front the Redis Cluster at " + redisUrl + ": the slow link is"
              + " a proxy in front of one server, and a cluster's core reaches the nodes the"
              + " cluster names, past the proxy. Give " + PrimeTestExtension.REDIS_PARAMETER
              + " a redis:// URL of one server, or leave OPTIMUS_SLOW_LINK out");
    }
    if (scheme.equals("rediss")) {
      throw new ExtensionConfigurationException(
          "OPTIMUS_SLOW_LINK cannot front the Redis at " + redisUrl + ": its TLS certificate"
              + " would be checked against the proxy's address, 127.0.0.1. Give "
              + PrimeTestExtension.REDIS_PARAMETER + " a redis:// URL (no TLS), or leave"
              + " OPTIMUS_SLOW_LINK out");
    }
    if (!scheme.equals("redis") || redis.getHost() == null) {
      throw new ExtensionConfigurationException(
          "OPTIMUS_SLOW_LINK cannot front the Redis at '" + redisUrl + "': give a URL"
              + " redis://[user[:password]@]host[:port][/database]");
    }
    return redis;
  }

  /** The Redis URL with the proxy's address: user, password and database kept. */
  private static String proxiedUrl(URI redis, InetSocketAddress local) {
    String host = local.getAddress().getHostAddress();
    if (host.indexOf(':') >= 0) {
      host = "[" + host + "]";
    }
    StringBuilder url = new StringBuilder("redis://");
    if (redis.getRawUserInfo() != null) {
      url.append(redis.getRawUserInfo()).append('@');
    }
    url.append(host).append(':').append(local.getPort());
    if (redis.getRawPath() != null) {
      url.append(redis.getRawPath());
    }
    if (redis.getRawQuery() != null) {
      url.append('?').append(redis.getRawQuery());
    }
    return url.toString();
  }

  // ------------------------------------------------------------------ the proxy's thread

  private void run() {
    try {
      while (!closed) {
        long wait = writeDue();
        if (wait < 0) {
          selector.select();
        } else if (wait >= ONE_MILLI) {
          selector.select(TimeUnit.NANOSECONDS.toMillis(wait));
        } else {
          if (wait > 0) {
            LockSupport.parkNanos(wait);
          }
          selector.selectNow();
        }
        for (SelectionKey key : selector.selectedKeys()) {
          handle(key);
        }
        selector.selectedKeys().clear();
      }
    } catch (IOException | RuntimeException e) {
      // end, closing everything, so the cores see their connections drop; close() reports it
      failure = e;
    } finally {
      for (Connection connection : List.copyOf(connections)) {
        connection.close();
      }
      quietly(server);
      try {
        selector.close();
      } catch (IOException e) {
        // nothing more to release
      }
    }
  }

  private void handle(SelectionKey key) {
    if (!key.isValid()) {
      return;
    }
    if (key.channel() == server) {
      accept();
      return;
    }
    Side side = (Side) key.attachment();
    Connection connection = side.connection;
    try {
      if (key.isConnectable()) {
        connection.connected = side.channel.finishConnect();
      }
      if (key.isValid() && key.isReadable()) {
        read(side);
      }
      if (key.isValid() && key.isWritable()) {
        write(side.outgoing, System.nanoTime());
      }
      if (!connection.isClosed()) {
        connection.updateInterest();
      }
    } catch (IOException | CancelledKeyException e) {
      connection.close();
    }
  }

  private void accept() {
    SocketChannel client = null;
    SocketChannel upstream = null;
    try {
      client = server.accept();
      if (client == null) {
        return;
      }
      upstream = SocketChannel.open();
      for (SocketChannel channel : List.of(client, upstream)) {
        channel.configureBlocking(false);
        channel.setOption(StandardSocketOptions.TCP_NODELAY, true);
      }
      boolean connected = upstream.connect(target);
      Connection connection = new Connection(client, upstream, connected);
      connections.add(connection);
      connection.updateInterest();
    } catch (IOException e) {
      // Redis refused or is out of reach: the core sees its connection closed, as without a proxy
      quietly(client);
      quietly(upstream);
    }
  }

  private void read(Side side) throws IOException {
    Direction direction = side.incoming;
    readBuffer.clear();
    int n = side.channel.read(readBuffer);
    if (n < 0) {
      direction.eofRead = true;
      direction.queue.add(new Chunk(System.nanoTime() + delayNanos, null));
      return;
    }
    if (n == 0) {
      return;
    }
    readBuffer.flip();
    ByteBuffer copy = ByteBuffer.allocate(n);
    copy.put(readBuffer).flip();
    direction.queue.add(new Chunk(System.nanoTime() + delayNanos, copy));
    direction.queued += n;
  }

  /**
   * Writes every chunk that is due, on every connection.
   *
   * @return nanoseconds until the next chunk is due, or -1 if none waits for its time
   */
  private long writeDue() {
    long now = System.nanoTime();
    long next = -1;
    for (Connection connection : List.copyOf(connections)) {
      try {
        for (Direction direction : connection.directions) {
          if (!connection.connected || direction.blocked) {
            continue;
          }
          write(direction, now);
          Chunk head = direction.queue.peek();
          if (head != null && !direction.blocked) {
            long wait = Math.max(0, head.due - now);
            next = next < 0 ? wait : Math.min(next, wait);
          }
        }
        if (connection.bothEnded()) {
          connection.close();
        } else {
          connection.updateInterest();
        }
      } catch (IOException | CancelledKeyException e) {
        connection.close();
      }
    }
    return next;
  }

  /** Writes the chunks of {@code direction} due by {@code now}, as far as the socket takes them. */
  private static void write(Direction direction, long now) throws IOException {
    direction.blocked = false;
    while (!direction.queue.isEmpty()) {
      Chunk head = direction.queue.peek();
      if (head.due - now > 0) {
        return;
      }
      if (head.data == null) {
        direction.queue.poll();
        direction.to.shutdownOutput();
        direction.eofWritten = true;
        return;
      }
      int n = direction.to.write(head.data);
      direction.queued -= n;
      if (head.data.hasRemaining()) {
        direction.blocked = true; // the socket is full: go on when it is writable
        return;
      }
      direction.queue.poll();
    }
  }

  private static void quietly(Channel channel) {
    if (channel != null) {
      try {
        channel.close();
      } catch (IOException e) {
        // closing anyway
      }
    }
  }

  /** A chunk of bytes due at {@code due}, or the end of the stream ({@code data} null). */
  private record Chunk(long due, ByteBuffer data) {}

  /** The bytes on their way from one socket to the other. */
  private static final class Direction {
    final SocketChannel to;
    final ArrayDeque<Chunk> queue = new ArrayDeque<>();
    int queued;
    boolean eofRead;
    boolean eofWritten;
    boolean blocked;

    Direction(SocketChannel to) {
      this.to = to;
    }
  }

  /** One socket of a connection: what it reads ({@code incoming}) and what it writes. */
  private static final class Side {
    final Connection connection;
    final SocketChannel channel;
    final Direction incoming;
    final Direction outgoing;

    Side(Connection connection, SocketChannel channel, Direction incoming, Direction outgoing) {
      this.connection = connection;
      this.channel = channel;
      this.incoming = incoming;
      this.outgoing = outgoing;
    }
  }

  /** A proxied connection: the core's socket and the socket to Redis. */
  private final class Connection {
    final Direction up;
    final Direction down;
    final List<Direction> directions;
    final SelectionKey clientKey;
    final SelectionKey upstreamKey;
    boolean connected;
    private boolean ended;

    Connection(SocketChannel client, SocketChannel upstream, boolean connected)
        throws IOException {
      this.connected = connected;
      this.up = new Direction(upstream);
      this.down = new Direction(client);
      this.directions = List.of(up, down);
      this.clientKey = client.register(selector, 0);
      this.upstreamKey = upstream.register(selector, connected ? 0 : SelectionKey.OP_CONNECT);
      clientKey.attach(new Side(this, client, up, down));
      upstreamKey.attach(new Side(this, upstream, down, up));
    }

    boolean isClosed() {
      return ended;
    }

    boolean bothEnded() {
      return up.eofWritten && down.eofWritten;
    }

    /** Reads a side while its queue has room; writes when a chunk waits for room in the socket. */
    void updateInterest() {
      if (ended) {
        return;
      }
      clientKey.interestOps(ops(up, down));
      upstreamKey.interestOps(connected ? ops(down, up) : SelectionKey.OP_CONNECT);
    }

    private int ops(Direction incoming, Direction outgoing) {
      int ops = 0;
      if (!incoming.eofRead && incoming.queued < QUEUE_LIMIT) {
        ops |= SelectionKey.OP_READ;
      }
      if (outgoing.blocked) {
        ops |= SelectionKey.OP_WRITE;
      }
      return ops;
    }

    void close() {
      if (ended) {
        return;
      }
      ended = true;
      connections.remove(this);
      quietly(clientKey.channel());
      quietly(upstreamKey.channel());
    }
  }
}
