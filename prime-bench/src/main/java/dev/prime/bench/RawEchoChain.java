package dev.prime.bench;

import java.nio.charset.StandardCharsets;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.atomic.AtomicReference;
import redis.clients.jedis.Jedis;
import redis.clients.jedis.Pipeline;
import redis.clients.jedis.Response;
import redis.clients.jedis.util.KeyValue;

/**
 * The baseline Optimus is measured against: a chain of echo threads over plain Redis lists with
 * plain Jedis, no envelope, no codec, no acknowledgement. Echo {@code i} pops from list
 * {@code i} and pushes what it got to list {@code i + 1}; a client pushes to list 0 and pops from
 * list {@code hops}.
 *
 * <p>Two ways to echo: {@link Mode#ONE_BY_ONE} ({@code BLPOP} then {@code RPUSH}, one value at a
 * time: the latency loop) and {@link Mode#BATCHED} (like an Optimus service: block for the first
 * value, then one pipelined round trip pushes what was taken and pops up to {@link #BATCH} more).
 *
 * <p>Design note. Each echo is a platform thread with its own connection, named
 * {@code raw-echo-<i>}; blocking pops ask Redis for at most {@link #POLL_SECONDS}, so
 * {@link #close} stops every thread within that time by setting a flag. The first failure of an
 * echo thread is kept and rethrown to the client, so a broken baseline fails instead of hanging.
 * The client side is not thread-safe (one benchmark thread uses it).
 */
final class RawEchoChain implements AutoCloseable {
  /** The most values one batched echo step pops. */
  static final int BATCH = 256;

  private static final double POLL_SECONDS = 0.1;
  private static final Duration CLIENT_TIMEOUT = Duration.ofSeconds(30);

  /** How the echo threads move values. */
  enum Mode {
    /** {@code BLPOP} one value, {@code RPUSH} it. */
    ONE_BY_ONE,
    /** Pipelined: push the values taken and pop up to {@link #BATCH} more, in one round trip. */
    BATCHED
  }

  private final byte[][] lists;
  private final Jedis client;
  private final List<Thread> threads = new ArrayList<>();
  private final AtomicReference<Throwable> failure = new AtomicReference<>();
  private volatile boolean stopped;

  /** Starts {@code hops} echo threads on the Redis of {@code rig}. */
  RawEchoChain(RedisRig rig, int hops, Mode mode) {
    lists = new byte[hops + 1][];
    for (int i = 0; i <= hops; i++) {
      lists[i] = ("raw:{bench}:" + i).getBytes(StandardCharsets.UTF_8);
    }
    client = rig.connect();
    client.del(lists);
    for (int i = 0; i < hops; i++) {
      Jedis jedis = rig.connect();
      byte[] in = lists[i];
      byte[] out = lists[i + 1];
      Runnable loop = mode == Mode.ONE_BY_ONE ? () -> echoOneByOne(jedis, in, out) : () -> echoBatched(jedis, in, out);
      Thread thread = new Thread(() -> {
        try (jedis) {
          loop.run();
        } catch (RuntimeException | Error e) {
          failure.compareAndSet(null, e);
        }
      }, "raw-echo-" + i);
      thread.setDaemon(true);
      threads.add(thread);
      thread.start();
    }
  }

  /** One synchronous call: pushes {@code value} to the first list and waits for it at the end. */
  byte[] call(byte[] value) {
    client.rpush(lists[0], value);
    KeyValue<byte[], byte[]> echoed = client.blpop((double) CLIENT_TIMEOUT.toSeconds(), lists[lists.length - 1]);
    if (echoed == null) {
      throw timeout(1);
    }
    return echoed.getValue();
  }

  /** Pushes {@code values} to the first list in one command. */
  void send(byte[][] values) {
    client.rpush(lists[0], values);
  }

  /** Pops {@code count} values from the last list (in batches); returns the sum of their sizes. */
  long receive(int count) {
    byte[] last = lists[lists.length - 1];
    long bytes = 0;
    int received = 0;
    while (received < count) {
      List<byte[]> some = client.lpop(last, Math.min(BATCH, count - received));
      if (some == null || some.isEmpty()) {
        KeyValue<byte[], byte[]> one = client.blpop((double) CLIENT_TIMEOUT.toSeconds(), last);
        if (one == null) {
          throw timeout(count - received);
        }
        some = List.of(one.getValue());
      }
      for (byte[] value : some) {
        bytes += value.length;
      }
      received += some.size();
    }
    return bytes;
  }

  private void echoOneByOne(Jedis jedis, byte[] in, byte[] out) {
    while (!stopped) {
      KeyValue<byte[], byte[]> taken = jedis.blpop(POLL_SECONDS, in);
      if (taken != null) {
        jedis.rpush(out, taken.getValue());
      }
    }
  }

  private void echoBatched(Jedis jedis, byte[] in, byte[] out) {
    List<byte[]> taken = List.of();
    while (!stopped) {
      if (taken.isEmpty()) {
        KeyValue<byte[], byte[]> one = jedis.blpop(POLL_SECONDS, in);
        if (one == null) {
          continue;
        }
        taken = List.of(one.getValue());
      }
      Pipeline pipeline = jedis.pipelined();
      pipeline.rpush(out, taken.toArray(new byte[0][]));
      Response<List<byte[]>> next = pipeline.lpop(in, BATCH);
      pipeline.sync();
      List<byte[]> more = next.get();
      taken = more == null ? List.of() : more;
    }
  }

  private IllegalStateException timeout(int missing) {
    Throwable cause = failure.get();
    return new IllegalStateException(
        missing + " value(s) did not come through the raw echo chain within " + CLIENT_TIMEOUT
            + (cause == null ? "" : "; an echo thread failed"), cause);
  }

  @Override
  public void close() {
    stopped = true;
    try {
      for (Thread thread : threads) {
        thread.join(Duration.ofSeconds(5).toMillis());
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    } finally {
      client.close();
    }
  }
}
