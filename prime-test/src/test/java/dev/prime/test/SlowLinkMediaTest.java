package dev.prime.test;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.platform.engine.discovery.DiscoverySelectors.selectClass;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.OptimusCore;
import java.io.ByteArrayOutputStream;
import java.io.DataInputStream;
import java.io.IOException;
import java.io.OutputStream;
import java.net.ConnectException;
import java.net.InetSocketAddress;
import java.net.Socket;
import java.net.URI;
import java.nio.charset.StandardCharsets;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.TimeUnit;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.extension.ExtensionConfigurationException;
import org.junit.platform.engine.TestExecutionResult;
import org.junit.platform.testkit.engine.EngineExecutionResults;
import org.junit.platform.testkit.engine.EngineTestKit;
import org.junit.platform.testkit.engine.Event;
import org.junit.platform.testkit.engine.Events;
import redis.clients.jedis.Jedis;

/**
 * {@link Media#OPTIMUS_SLOW_LINK} run by JUnit's own engine (through the platform's test kit) on
 * the small test classes nested here, which Surefire does not run by themselves.
 */
class SlowLinkMediaTest {
  /** The name of every slow link's thread starts with this, then its port. */
  static final String THREAD_PREFIX = "prime-test-slow-link-";

  static final String DELAY = "prime.test.slowLink.delay";

  /** What the nested tests saw; cleared before each kit run. */
  static final List<PrimeCore> CORES = new CopyOnWriteArrayList<>();

  static final List<String> LOG = new CopyOnWriteArrayList<>();

  @BeforeEach
  void clear() {
    CORES.clear();
    LOG.clear();
  }

  // ------------------------------------------------------------------ a topology over the link

  static class ThermometerOnBothOptimus {
    @PrimeTest(media = {Media.OPTIMUS, Media.OPTIMUS_SLOW_LINK})
    void reportsEveryReadingInFahrenheit(PrimeCore core, Media media) {
      EventBlock<Double> thermometer = new EventBlock<>();
      Reader<String> display =
          core.source("thermometer", thermometer)
              .then(core.chain("convert", (Double c) -> c * 9 / 5 + 32))
              .then(core.chain("format", (Double f) -> Math.round(f) + " F"))
              .reader();
      core.start();
      thermometer.publish(21.5);
      thermometer.publish(100.0);

      ReaderAssert.assertThat(display)
          .within(Duration.ofSeconds(10))
          .emits("71 F", "212 F")
          .emitsNothingWithin(Duration.ofMillis(100));
      CORES.add(core);
      LOG.add(media + " " + slowLinkThreads());
    }
  }

  @Test
  void aTopologyTestPassesOverTheSlowLinkWhoseCoreReachesTheClasssRedisThroughItsProxy() {
    EngineExecutionResults results = run(ThermometerOnBothOptimus.class);

    results.testEvents().assertStatistics(s -> s.started(2).succeeded(2).failed(0));
    assertEquals(List.of("Optimus", "Optimus, slow link"), names(results.testEvents().succeeded()));
    OptimusCore plain = assertInstanceOf(OptimusCore.class, CORES.get(0));
    OptimusCore slow = assertInstanceOf(OptimusCore.class, CORES.get(1));
    assertTrue(slow.name().matches("test-optimus-slow-link-\\d+-[0-9a-z]{1,4}"), slow.name());
    assertEquals("127.0.0.1", URI.create(slow.getRedisUrl()).getHost());
    assertNotEquals(port(plain), port(slow), "the slow run's core reaches Redis elsewhere");
    assertEquals("OPTIMUS []", LOG.get(0), "no slow link for the plain run");
    assertEquals(
        "OPTIMUS_SLOW_LINK [" + THREAD_PREFIX + port(slow) + "]",
        LOG.get(1),
        "the slow run's core reaches Redis through the slow link's port");
    assertTrue(CORES.stream().allMatch(PrimeCore::isClosed), "every core closed after its run");
  }

  /** Larger than what the link queues for one direction (256 KiB) and than socket buffers. */
  static final int LARGE = 3 * 1024 * 1024;

  static class LargeValues {
    @PrimeTest(media = Media.OPTIMUS_SLOW_LINK)
    void carriesValuesLargerThanTheLinksQueuesWhole(PrimeCore core) {
      EventBlock<String> camera = new EventBlock<>();
      Reader<String> framed =
          core.source("camera", camera).then(core.chain("frame", (String s) -> "[" + s + "]")).reader();
      core.start();
      List<String> expected = new ArrayList<>();
      for (char c = 'a'; c < 'd'; c++) {
        String image = (c + "0123456789").repeat(LARGE / 11);
        camera.publish(image);
        expected.add("[" + image + "]");
      }
      ReaderAssert.assertThat(framed).within(Duration.ofSeconds(30)).emitsAll(expected);
      LOG.add("carried " + expected.size());
    }
  }

  @Test
  void valuesLargerThanTheLinksQueuesCrossItWhole() {
    passes(LargeValues.class, 1);
    assertEquals(List.of("carried 3"), LOG);
  }

  /** How many replies of a megabyte the slow reader asks for in one write. */
  static final int GETS = 48;

  static class SlowReader {
    /**
     * Asks Redis, through the run's link, for a megabyte value {@value #GETS} times in one write
     * on a socket that then reads nothing while Redis holds half the replies for 500 ms (its
     * output buffer, seen on another connection): the link has filled that socket, stopped on a
     * write it could not finish, and stopped reading Redis. Then every byte must arrive, in
     * order.
     */
    @PrimeTest(media = Media.OPTIMUS_SLOW_LINK)
    void getsEveryByteOfRepliesTheLinkHadToHoldBack(PrimeCore core) throws IOException {
      URI link = URI.create(((OptimusCore) core).getRedisUrl());
      byte[] value = new byte[1024 * 1024];
      for (int i = 0; i < value.length; i++) {
        value[i] = (byte) (i % 251);
      }
      byte[] key = ("prime:{" + core.name() + "}:slow-link-probe").getBytes(StandardCharsets.UTF_8);
      try (Socket socket = new Socket();
          Jedis watcher = new Jedis(link)) {
        socket.connect(new InetSocketAddress(link.getHost(), link.getPort()), 2000);
        socket.setSoTimeout(10_000);
        OutputStream out = socket.getOutputStream();
        DataInputStream in = new DataInputStream(socket.getInputStream());
        out.write(command("CLIENT", "SETNAME".getBytes(StandardCharsets.US_ASCII),
            "slow-reader".getBytes(StandardCharsets.US_ASCII)));
        out.write(command("SET", key, value));
        out.flush();
        assertEquals("+OK", line(in));
        assertEquals("+OK", line(in));
        ByteArrayOutputStream gets = new ByteArrayOutputStream();
        for (int i = 0; i < GETS; i++) {
          gets.write(command("GET", key));
        }
        out.write(gets.toByteArray());
        out.flush();

        // Redis keeps half the replies for 500 ms: more than the sockets and the link's queue
        // hold, so the link stopped on a write the reader's socket did not take, and stopped
        // reading Redis until it does
        long half = (long) GETS * value.length / 2;
        long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(10);
        long held = 0;
        for (int i = 0; i < 10_000 && held < half && System.nanoTime() - deadline < 0; i++) {
          held = outputBufferOf(watcher.clientList(), "slow-reader");
        }
        assertTrue(held >= half, "Redis held at most " + held + " bytes of replies to the reader"
            + " that reads nothing, expected " + half);
        long quietEnd = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(500);
        long least = held;
        for (int i = 0; i < 10_000 && System.nanoTime() - quietEnd < 0; i++) {
          least = Math.min(least, outputBufferOf(watcher.clientList(), "slow-reader"));
        }
        assertTrue(least >= half, "Redis's replies to the reader that reads nothing fell to "
            + least + " bytes within 500 ms, expected " + half + " or more: the link read on"
            + " what it could not write");

        for (int i = 0; i < GETS; i++) {
          assertEquals("$" + value.length, line(in), "reply " + (i + 1));
          byte[] got = new byte[value.length];
          in.readFully(got);
          assertTrue(Arrays.equals(value, got), "reply " + (i + 1) + " differs from the value set");
          assertEquals("", line(in));
        }
        watcher.del(key);
      }
      LOG.add("read " + GETS + " replies");
    }

    /** The {@code omem} (bytes Redis could not send yet) of the client named {@code name}. */
    private static long outputBufferOf(String clients, String name) {
      for (String client : clients.split("\n")) {
        if (client.contains(" name=" + name + " ")) {
          Matcher m = Pattern.compile(" omem=(\\d+) ").matcher(client);
          assertTrue(m.find(), client);
          return Long.parseLong(m.group(1));
        }
      }
      throw new AssertionError("no client " + name + " in " + clients);
    }

    private static byte[] command(String name, byte[]... args) throws IOException {
      ByteArrayOutputStream out = new ByteArrayOutputStream();
      out.write(("*" + (args.length + 1) + "\r\n$" + name.length() + "\r\n" + name + "\r\n")
          .getBytes(StandardCharsets.US_ASCII));
      for (byte[] arg : args) {
        out.write(("$" + arg.length + "\r\n").getBytes(StandardCharsets.US_ASCII));
        out.write(arg);
        out.write("\r\n".getBytes(StandardCharsets.US_ASCII));
      }
      return out.toByteArray();
    }

    /** A line of Redis's answer, without its CRLF. */
    private static String line(DataInputStream in) throws IOException {
      StringBuilder line = new StringBuilder();
      for (int i = 0; i < 64; i++) {
        int b = in.readUnsignedByte();
        if (b == '\r') {
          assertEquals('\n', in.readUnsignedByte());
          return line.toString();
        }
        line.append((char) b);
      }
      throw new AssertionError("no line end in " + line);
    }
  }

  @Test
  void repliesTheLinkHadToHoldBackForASlowReaderCrossItWhole() {
    passes(SlowReader.class, 1);
    assertEquals(List.of("read " + GETS + " replies"), LOG);
  }

  // ------------------------------------------------------------------ the delay

  static final int CALLS = 5;
  static final Duration CALL_DELAY = Duration.ofMillis(20);

  static class TimedCalls {
    @PrimeTest(media = {Media.OPTIMUS, Media.OPTIMUS_SLOW_LINK})
    void callsAChainOneAfterTheOther(PrimeCore core, Media media) {
      Block<Integer, Integer> twice = core.chain("twice", (Integer x) -> 2 * x).toBlock();
      core.start();
      assertEquals(0, twice.process(0)); // the thread's first call connects: not timed
      long start = System.nanoTime();
      for (int i = 1; i <= CALLS; i++) {
        assertEquals(2 * i, twice.process(i));
      }
      LOG.add(media + " " + (System.nanoTime() - start));
    }
  }

  @Test
  void everyByteTakesTheDelayEachWaySoACallOverTheLinkTakesFourDelaysAtLeast() {
    EngineExecutionResults results =
        EngineTestKit.engine("junit-jupiter")
            .configurationParameter(DELAY, CALL_DELAY.toMillis() + "ms")
            .selectors(selectClass(TimedCalls.class))
            .execute();

    results.testEvents().assertStatistics(s -> s.started(2).succeeded(2));
    assertEquals(2, LOG.size(), LOG.toString());
    long plain = nanosOf(LOG.get(0), "OPTIMUS ");
    long slow = nanosOf(LOG.get(1), "OPTIMUS_SLOW_LINK ");
    // a call crosses the link four times: the request to Redis, to the service, its result to
    // Redis, to the caller
    long least = CALLS * 4 * CALL_DELAY.toNanos();
    System.out.printf(
        "%d calls: %.1f ms on Optimus, %.1f ms over the slow link of %d ms each way%n",
        CALLS, plain / 1e6, slow / 1e6, CALL_DELAY.toMillis());
    assertTrue(
        slow >= least,
        CALLS + " calls over a link of " + CALL_DELAY.toMillis() + " ms each way took "
            + slow / 1_000_000 + " ms, expected at least " + least / 1_000_000 + " ms");
    assertTrue(
        slow < 5 * least,
        CALLS + " calls took " + slow / 1_000_000 + " ms, more than 5 times the "
            + least / 1_000_000 + " ms of the delay: is the delay longer than asked?");
  }

  // ------------------------------------------------------------------ bad settings

  static class InMemoryAndSlow {
    @PrimeTest(media = {Media.LIBERTY, Media.OPTIMUS_SLOW_LINK})
    void starts(PrimeCore core) {
      core.start();
    }
  }

  @Test
  void aDelayParameterThatIsNotADelayFailsTheSlowLinkRunNamingTheParameterAndAnExample() {
    for (String bad : List.of("2", "2 seconds", "PT0.002S", "-1ms", "10000.5ms", "1.ms")) {
      EngineExecutionResults results =
          EngineTestKit.engine("junit-jupiter")
              .configurationParameter(DELAY, bad)
              .selectors(selectClass(InMemoryAndSlow.class))
              .execute();

      assertEquals(List.of("Liberty"), names(results.testEvents().succeeded()), bad);
      Event failed = results.testEvents().failed().list().get(0);
      assertEquals("Optimus, slow link", failed.getTestDescriptor().getDisplayName());
      Throwable thrown = failure(failed);
      assertInstanceOf(ExtensionConfigurationException.class, thrown, bad);
      assertTrue(
          thrown.getMessage().startsWith(
              "the JUnit configuration parameter prime.test.slowLink.delay is '" + bad + "',"),
          thrown.getMessage());
      assertTrue(thrown.getMessage().contains("like prime.test.slowLink.delay=2ms"), thrown.getMessage());
    }
    for (String good : List.of("0ms", "0.25ms", "3ms", "3 MS")) {
      EngineTestKit.engine("junit-jupiter")
          .configurationParameter(DELAY, good)
          .selectors(selectClass(InMemoryAndSlow.class))
          .execute()
          .testEvents()
          .assertStatistics(s -> s.succeeded(2).failed(0));
    }
  }

  @Test
  void aRedisTheLinkCannotFrontIsRefusedSayingWhy() {
    String tls = slowRunFailure("rediss://127.0.0.1:6380");
    assertTrue(
        tls.startsWith("OPTIMUS_SLOW_LINK cannot front the Redis at rediss://127.0.0.1:6380: its"
            + " TLS certificate would be checked against the proxy's address"),
        tls);
    String cluster = slowRunFailure("redis-cluster://127.0.0.1:7000,127.0.0.1:7001");
    assertTrue(
        cluster.startsWith("OPTIMUS_SLOW_LINK cannot front the Redis Cluster at"
            + " redis-cluster://127.0.0.1:7000,127.0.0.1:7001"),
        cluster);
    assertTrue(cluster.contains("Give prime.test.redis a redis:// URL of one server"), cluster);
  }

  private static String slowRunFailure(String redisUrl) {
    EngineExecutionResults results =
        EngineTestKit.engine("junit-jupiter")
            .configurationParameter("prime.test.redis", redisUrl)
            .selectors(selectClass(InMemoryAndSlow.class))
            .execute();
    assertEquals(List.of("Liberty"), names(results.testEvents().succeeded()), redisUrl);
    return failure(results.testEvents().failed().list().get(0)).getMessage();
  }

  // ------------------------------------------------------------------ one link per class

  static class TwoSlowRuns {
    @PrimeTest(media = {Media.OPTIMUS_SLOW_LINK, Media.OPTIMUS_SLOW_LINK})
    void records(PrimeCore core) throws InterruptedException {
      EventBlock<String> sensor = new EventBlock<>();
      Reader<String> reader = core.source("sensor", sensor).reader();
      core.start();
      sensor.publish("over the link");
      assertEquals("over the link", reader.take(Duration.ofSeconds(10)).orElseThrow());
      LOG.add(port((OptimusCore) core) + " " + slowLinkThreads());
    }
  }

  @Test
  void theRunsOfAClassShareOneSlowLinkWhoseThreadAndPortAreGoneAfterTheClass()
      throws IOException {
    assertEquals(List.of(), slowLinkThreads(), "no slow link before");

    EngineExecutionResults results = run(TwoSlowRuns.class);

    results.testEvents().assertStatistics(s -> s.started(2).succeeded(2));
    assertEquals(2, LOG.size(), LOG.toString());
    assertEquals(LOG.get(0), LOG.get(1), "one slow link for the class");
    int port = Integer.parseInt(LOG.get(0).substring(0, LOG.get(0).indexOf(' ')));
    assertEquals(port + " [" + THREAD_PREFIX + port + "]", LOG.get(0));
    assertEquals(List.of(), slowLinkThreads(), "the slow link's thread after the class");
    try (Socket socket = new Socket()) {
      socket.connect(new InetSocketAddress("127.0.0.1", port), 2000);
      throw new AssertionError("the class's slow link still listens on port " + port);
    } catch (ConnectException expected) {
      // closed after the class
    }
  }

  // ------------------------------------------------------------------ the user's Redis

  static class UsesTheUsersRedis {
    static String url;

    @PrimeTest(media = Media.OPTIMUS_SLOW_LINK)
    void passes(PrimeCore core) throws InterruptedException {
      publishAndRead(core);
    }

    @PrimeTest(media = Media.OPTIMUS_SLOW_LINK)
    void fails(PrimeCore core) throws InterruptedException {
      publishAndRead(core);
      throw new AssertionError("fails on purpose");
    }

    private static void publishAndRead(PrimeCore core) throws InterruptedException {
      LOG.add(KeyLeavingRun.run(core, url));
      CORES.add(core);
    }
  }

  @Test
  void theLinkFrontsTheRedisOfTheConfigurationParameterAndARunsKeysAreDeletedAfterIt() {
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        Jedis jedis = new Jedis(URI.create(redis.getUri()))) {
      jedis.set("someone-elses-key", "kept");
      UsesTheUsersRedis.url = redis.getUri();
      EngineExecutionResults results =
          EngineTestKit.engine("junit-jupiter")
              .configurationParameter("prime.test.redis", redis.getUri())
              .selectors(selectClass(UsesTheUsersRedis.class))
              .execute();

      results.testEvents().assertStatistics(s -> s.succeeded(1).failed(1));
      assertEquals(2, LOG.size(), LOG.toString());
      KeyLeavingRun.assertEveryRunHadKeysAndLeftNone(LOG, CORES, redis.getUri());
      for (PrimeCore core : CORES) {
        assertNotEquals(redis.getPort(), port((OptimusCore) core), "the core reaches Redis through the link");
      }
      assertEquals(Set.of("someone-elses-key"), jedis.keys("*"), "only the key that was not a run's is left");
      assertTrue(redis.isRunning(), "a Redis the extension did not start is not stopped");
    }
  }

  // ------------------------------------------------------------------ helpers

  /** The names of the slow links' threads of this JVM, sorted. */
  static List<String> slowLinkThreads() {
    return Thread.getAllStackTraces().keySet().stream()
        .map(Thread::getName)
        .filter(name -> name.startsWith(THREAD_PREFIX))
        .sorted()
        .toList();
  }

  private static long nanosOf(String line, String prefix) {
    assertTrue(line.startsWith(prefix), line);
    return Long.parseLong(line.substring(prefix.length()));
  }

  /** Runs {@code testClass}, expecting {@code runs} runs to pass; else fails with the first failure. */
  static void passes(Class<?> testClass, int runs) {
    EngineExecutionResults results = run(testClass);
    results.testEvents().failed().stream().findFirst().ifPresent(failed -> {
      throw new AssertionError(
          failed.getTestDescriptor().getDisplayName() + " run failed: " + failure(failed), failure(failed));
    });
    results.testEvents().assertStatistics(s -> s.started(runs).succeeded(runs));
  }

  static EngineExecutionResults run(Class<?> testClass) {
    return EngineTestKit.engine("junit-jupiter").selectors(selectClass(testClass)).execute();
  }

  static List<String> names(Events events) {
    return events.stream().map(e -> e.getTestDescriptor().getDisplayName()).toList();
  }

  static int port(OptimusCore core) {
    return URI.create(core.getRedisUrl()).getPort();
  }

  static Throwable failure(Event event) {
    return event.getPayload(TestExecutionResult.class).orElseThrow().getThrowable().orElseThrow();
  }
}
