package dev.prime.faults;

import java.io.ByteArrayOutputStream;
import java.io.IOException;
import java.io.InputStream;
import java.io.OutputStream;
import java.io.UncheckedIOException;
import java.net.InetAddress;
import java.net.ServerSocket;
import java.net.Socket;
import java.nio.charset.StandardCharsets;
import java.time.Duration;
import java.util.Set;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicReference;
import java.util.concurrent.locks.LockSupport;

/**
 * A TCP proxy on 127.0.0.1 in front of a Redis, with the network faults the suite needs:
 * forward; {@link #delay} every chunk; {@link #freeze()} both directions (connections stay open,
 * nothing moves, as in a partition) until {@link #thaw()}; {@link #cutAll()} connections; and
 * {@link #cutAfterNextClientWrite} (forward one client write that contains given bytes, then close
 * that connection as soon as Redis answers it, so the write took effect and the client never sees
 * the answer: closing before the answer would race with Redis reading the write).
 *
 * <p>Design note. Two daemon threads per connection pump the bytes (client to server, server to
 * client) and never stop reading: while frozen, what they read is held in the connection (under
 * its lock) instead of written, and {@link #thaw()} delivers it, like a healed network. Because
 * the pumps keep reading, a client that gives up on a frozen connection and closes it is seen at
 * once; that close is recorded with its time, which is how a test sees when a client noticed the
 * freeze. {@link #close()} closes every socket, which ends every thread.
 */
final class FaultProxy implements AutoCloseable {
  private final int targetPort;
  private final ServerSocket server;
  private final Set<Connection> connections = ConcurrentHashMap.newKeySet();
  private final Object gate = new Object();
  private boolean frozen; // guarded by gate
  private long frozenAt; // guarded by gate
  private long firstClientCloseSinceFreeze = -1; // guarded by gate
  private volatile long delayNanos;
  private final AtomicReference<byte[]> cutPattern = new AtomicReference<>();
  private final AtomicReference<Trigger> trigger = new AtomicReference<>();
  private final AtomicReference<Trigger> answerHold = new AtomicReference<>();
  private final AtomicInteger cuts = new AtomicInteger();
  private final AtomicInteger accepted = new AtomicInteger();
  private final AtomicInteger threadNumbers = new AtomicInteger();

  FaultProxy(int targetPort) {
    this.targetPort = targetPort;
    try {
      server = new ServerSocket(0, 50, InetAddress.getLoopbackAddress());
    } catch (IOException e) {
      throw new UncheckedIOException(e);
    }
    daemon("accept", this::acceptLoop);
  }

  /** {@code redis://127.0.0.1:<proxy port>}. */
  String url() {
    return "redis://127.0.0.1:" + server.getLocalPort();
  }

  /** Holds every chunk back {@code delay} before forwarding it (zero: forward at once). */
  void delay(Duration delay) {
    delayNanos = delay.toNanos();
  }

  /** Stops moving bytes in both directions; connections stay open, new ones are accepted and frozen too. */
  void freeze() {
    synchronized (gate) {
      frozen = true;
      frozenAt = System.nanoTime();
      firstClientCloseSinceFreeze = -1;
    }
  }

  /** Moves bytes again, first those held during the freeze. */
  void thaw() {
    synchronized (gate) {
      frozen = false;
    }
    for (Connection connection : connections) connection.release();
  }

  /**
   * Waits until a client closes a connection after {@link #freeze()}: it noticed the freeze.
   *
   * @return nanoseconds from the freeze to that close, or -1 if none within {@code timeout}
   */
  long awaitClientNoticedFreeze(Duration timeout) throws InterruptedException {
    synchronized (gate) {
      long deadline = System.nanoTime() + timeout.toNanos();
      while (firstClientCloseSinceFreeze < 0) {
        long left = deadline - System.nanoTime();
        if (left <= 0) return -1;
        TimeUnit.NANOSECONDS.timedWait(gate, left);
      }
      return firstClientCloseSinceFreeze - frozenAt;
    }
  }

  /** Closes every open connection at once; returns how many there were. */
  int cutAll() {
    int n = 0;
    for (Connection connection : connections) {
      connection.close();
      n++;
    }
    return n;
  }

  /**
   * Arms a one-shot cut: the next client write that contains {@code pattern} is forwarded to the
   * server, and its connection is closed when the server's answer arrives, which is dropped.
   */
  void cutAfterNextClientWrite(byte[] pattern) {
    cutPattern.set(pattern.clone());
  }

  /**
   * Arms a one-shot trigger: the next client write that contains every one of {@code parts} runs
   * {@code action} on the proxy's thread before it is forwarded (a fault that strikes just as a
   * given command is sent, such as killing the server: the write then reaches no server).
   *
   * @return a latch that opens once {@code action} has run
   */
  CountDownLatch beforeNextClientWriteContaining(Runnable action, String... parts) {
    byte[][] patterns = new byte[parts.length][];
    for (int i = 0; i < parts.length; i++) patterns[i] = parts[i].getBytes(StandardCharsets.UTF_8);
    Trigger armed = new Trigger(patterns, action);
    trigger.set(armed);
    return armed.fired;
  }

  /**
   * Arms a one-shot hold: the next client write that contains every one of {@code parts} is
   * forwarded to the server, and from then on nothing the server sends on that connection reaches
   * the client (the connection stays open, as after a partition that struck just after the write;
   * other connections go on).
   *
   * @return a latch that opens once that write was forwarded
   */
  CountDownLatch holdAnswersAfterNextClientWriteContaining(String... parts) {
    byte[][] patterns = new byte[parts.length][];
    for (int i = 0; i < parts.length; i++) patterns[i] = parts[i].getBytes(StandardCharsets.UTF_8);
    Trigger armed = new Trigger(patterns, () -> {});
    answerHold.set(armed);
    return armed.fired;
  }

  /** Connections open now (each a client's socket and its upstream socket). */
  int openConnections() {
    return connections.size();
  }

  /** How many connections were cut after a marked client write was answered. */
  int cutsDone() {
    return cuts.get();
  }

  /** Connections accepted so far. */
  int acceptedConnections() {
    return accepted.get();
  }

  @Override
  public void close() {
    try {
      server.close();
    } catch (IOException e) {
      // closing anyway
    }
    cutAll();
    thaw();
  }

  private void acceptLoop() {
    while (!server.isClosed()) {
      Socket client;
      try {
        client = server.accept();
      } catch (IOException e) {
        return; // closed
      }
      Socket upstream;
      try {
        upstream = new Socket(InetAddress.getLoopbackAddress(), targetPort);
      } catch (IOException e) {
        closeQuietly(client); // the server is down: the client sees a refused connection
        continue;
      }
      try { // as Redis and Jedis do: a small write does not wait for the ACK of the one before
        client.setTcpNoDelay(true);
        upstream.setTcpNoDelay(true);
      } catch (IOException e) {
        closeQuietly(client);
        closeQuietly(upstream);
        continue;
      }
      accepted.incrementAndGet();
      Connection connection = new Connection(client, upstream);
      connections.add(connection);
      daemon("up", () -> connection.pump(true));
      daemon("down", () -> connection.pump(false));
    }
  }

  private boolean isFrozen() {
    synchronized (gate) {
      return frozen;
    }
  }

  private void clientClosed() {
    synchronized (gate) {
      if (frozen && firstClientCloseSinceFreeze < 0) {
        firstClientCloseSinceFreeze = System.nanoTime();
        gate.notifyAll();
      }
    }
  }

  private final class Connection {
    private final Socket client;
    private final Socket upstream;
    private volatile boolean cutOnAnswer;
    private volatile boolean holdsAnswers;
    private final ByteArrayOutputStream heldUp = new ByteArrayOutputStream(); // guarded by this
    private final ByteArrayOutputStream heldDown = new ByteArrayOutputStream(); // guarded by this

    Connection(Socket client, Socket upstream) {
      this.client = client;
      this.upstream = upstream;
    }

    void pump(boolean fromClient) {
      byte[] buffer = new byte[64 * 1024];
      Socket from = fromClient ? client : upstream;
      Socket to = fromClient ? upstream : client;
      try {
        InputStream in = from.getInputStream();
        OutputStream out = to.getOutputStream();
        while (true) {
          int n = in.read(buffer);
          if (n < 0) {
            if (fromClient) clientClosed();
            break;
          }
          if (!fromClient && cutOnAnswer) {
            cuts.incrementAndGet(); // the marked write was executed; its answer never arrives
            break;
          }
          if (!fromClient && holdsAnswers) continue; // held for good: the client never sees it
          long delay = delayNanos;
          if (delay > 0) LockSupport.parkNanos(delay);
          if (fromClient) markIfArmed(buffer, n); // before the write: its answer may come at once
          if (fromClient) fireIfArmed(buffer, n);
          Trigger hold = fromClient ? holdIfArmed(buffer, n) : null;
          forward(fromClient ? heldUp : heldDown, out, buffer, n);
          if (hold != null) hold.fired.countDown();
        }
      } catch (IOException e) {
        if (fromClient && !client.isClosed()) clientClosed();
      } finally {
        close();
      }
    }

    /** Writes the chunk to {@code out} after anything held, or holds it while the proxy is frozen. */
    private synchronized void forward(ByteArrayOutputStream held, OutputStream out, byte[] chunk, int length) throws IOException {
      if (isFrozen()) {
        held.write(chunk, 0, length);
        return;
      }
      if (held.size() > 0) {
        held.writeTo(out);
        held.reset();
      }
      out.write(chunk, 0, length);
      out.flush();
    }

    /** After a thaw: delivers what was held in both directions. */
    synchronized void release() {
      try {
        if (heldUp.size() > 0) {
          heldUp.writeTo(upstream.getOutputStream());
          upstream.getOutputStream().flush();
        }
        if (heldDown.size() > 0) {
          heldDown.writeTo(client.getOutputStream());
          client.getOutputStream().flush();
        }
      } catch (IOException e) {
        close(); // a side closed meanwhile: nothing to deliver to
      } finally {
        heldUp.reset();
        heldDown.reset();
      }
    }

    /** The armed answer hold, if this write matches it: from now on this connection's answers are held. */
    private Trigger holdIfArmed(byte[] chunk, int length) {
      Trigger armed = answerHold.get();
      if (armed != null && armed.matches(chunk, length) && answerHold.compareAndSet(armed, null)) {
        holdsAnswers = true;
        return armed;
      }
      return null;
    }

    private void markIfArmed(byte[] chunk, int length) {
      byte[] pattern = cutPattern.get();
      if (pattern != null && contains(chunk, length, pattern) && cutPattern.compareAndSet(pattern, null)) {
        cutOnAnswer = true;
      }
    }

    void close() {
      connections.remove(this);
      closeQuietly(client);
      closeQuietly(upstream);
    }
  }

  /** A one-shot action run before the first client write that contains all of {@code patterns}. */
  private record Trigger(byte[][] patterns, Runnable action, CountDownLatch fired) {
    Trigger(byte[][] patterns, Runnable action) {
      this(patterns, action, new CountDownLatch(1));
    }

    boolean matches(byte[] chunk, int length) {
      for (byte[] pattern : patterns) {
        if (!contains(chunk, length, pattern)) return false;
      }
      return true;
    }
  }

  private void fireIfArmed(byte[] chunk, int length) {
    Trigger armed = trigger.get();
    if (armed != null && armed.matches(chunk, length) && trigger.compareAndSet(armed, null)) {
      try {
        armed.action.run();
      } finally {
        armed.fired.countDown();
      }
    }
  }

  private static boolean contains(byte[] chunk, int length, byte[] pattern) {
    outer:
    for (int i = 0; i + pattern.length <= length; i++) {
      for (int j = 0; j < pattern.length; j++) {
        if (chunk[i + j] != pattern[j]) continue outer;
      }
      return true;
    }
    return false;
  }

  private static void closeQuietly(Socket socket) {
    try {
      socket.close();
    } catch (IOException e) {
      // gone either way
    }
  }

  private void daemon(String role, Runnable body) {
    Thread thread = new Thread(body, "fault-proxy-" + role + "-" + threadNumbers.incrementAndGet());
    thread.setDaemon(true);
    thread.start();
  }
}
