package dev.prime.test;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.platform.engine.discovery.DiscoverySelectors.selectClass;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.liberty.LibertyCore;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.OptimusCore;
import dev.prime.optimus.RedisUnavailableException;
import dev.prime.radiant.RadiantCore;
import java.io.IOException;
import java.lang.annotation.Retention;
import java.lang.annotation.RetentionPolicy;
import java.net.ConnectException;
import java.net.InetSocketAddress;
import java.net.Socket;
import java.net.URI;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.stream.Stream;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.MethodOrderer;
import org.junit.jupiter.api.Order;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.TestMethodOrder;
import org.junit.platform.engine.TestExecutionResult;
import org.junit.platform.testkit.engine.EngineExecutionResults;
import org.junit.platform.testkit.engine.EngineTestKit;
import org.junit.platform.testkit.engine.Event;
import org.junit.platform.testkit.engine.Events;
import redis.clients.jedis.Jedis;

/**
 * {@link PrimeTest} run by JUnit's own engine (through the platform's test kit) on the small test
 * classes nested here, which Surefire does not run by themselves.
 */
class PrimeTestExtensionTest {
  /** What the nested tests saw; cleared before each kit run. */
  static final List<PrimeCore> CORES = new CopyOnWriteArrayList<>();

  static final List<String> LOG = new CopyOnWriteArrayList<>();

  /** Cores a setup made that the extension refused. */
  static final List<PrimeCore> REFUSED = new CopyOnWriteArrayList<>();

  @BeforeEach
  void clear() {
    CORES.clear();
    LOG.clear();
    REFUSED.clear();
  }

  // ------------------------------------------------------------------ one run per media

  static class OnEveryMedia {
    @PrimeTest
    void records(PrimeCore core, Media media) {
      CORES.add(core);
      LOG.add(media + " " + core.getClass().getSimpleName() + " started=" + core.isStarted());
    }
  }

  /** Whether this JVM has a redis-server child (the embedded Redis of a test class). */
  static boolean redisServerRuns() {
    return ProcessHandle.current()
        .descendants()
        .anyMatch(p -> p.isAlive() && p.info().command().orElse("").contains("redis-server"));
  }

  @Test
  void runsOncePerMediaInOrderEachWithAFreshCoreOfThatMediaClosedAfterwards() {
    EngineExecutionResults results = run(OnEveryMedia.class);

    results.testEvents().assertStatistics(s -> s.started(3).succeeded(3).failed(0));
    assertEquals(List.of("Liberty", "Radiant", "Optimus"), names(results.testEvents().succeeded()));
    assertEquals(
        List.of(
            "LIBERTY LibertyCore started=false",
            "RADIANT RadiantCore started=false",
            "OPTIMUS OptimusCore started=false"),
        LOG);
    assertEquals(3, CORES.stream().map(PrimeCore::name).distinct().count(), names(CORES));
    assertTrue(CORES.stream().allMatch(PrimeCore::isClosed), "every core closed after its run");
    assertTrue(CORES.get(0).name().matches("test-liberty-\\d+-[0-9a-z]{1,4}"), CORES.get(0).name());
    assertTrue(CORES.get(2).name().matches("test-optimus-\\d+-[0-9a-z]{1,4}"), CORES.get(2).name());
  }

  static class FailsOnRadiant {
    @PrimeTest
    void failsOnRadiantOnly(PrimeCore core, Media media) {
      CORES.add(core);
      core.start();
      assertNotEquals(Media.RADIANT, media, "the Radiant run fails here");
    }
  }

  @Test
  void aFailingRunIsReportedUnderItsMediaAndItsCoreIsClosedAllTheSame() {
    EngineExecutionResults results = run(FailsOnRadiant.class);

    results.testEvents().assertStatistics(s -> s.started(3).succeeded(2).failed(1));
    Event failed = results.testEvents().failed().list().get(0);
    assertEquals("Radiant", failed.getTestDescriptor().getDisplayName());
    assertTrue(failure(failed).getMessage().startsWith("the Radiant run fails here"), failure(failed).getMessage());
    assertEquals(3, CORES.size());
    assertTrue(CORES.stream().allMatch(PrimeCore::isClosed), "the failed run's core is closed too");
  }

  static class LibertyAndRadiant {
    @PrimeTest(media = {Media.RADIANT, Media.LIBERTY})
    void records(PrimeCore core) {
      CORES.add(core);
      LOG.add("redis-server runs=" + redisServerRuns());
    }
  }

  static class OptimusOnly {
    @PrimeTest(media = Media.OPTIMUS)
    void records(PrimeCore core) {
      LOG.add("redis-server runs=" + redisServerRuns());
    }
  }

  @Test
  void runsOnlyOnTheMediaItNamesInTheirOrderAndStartsNoRedisWithoutOptimus() {
    EngineExecutionResults results = run(LibertyAndRadiant.class);
    run(OptimusOnly.class).testEvents().assertStatistics(s -> s.succeeded(1));

    assertEquals(List.of("Radiant", "Liberty"), names(results.testEvents().succeeded()));
    assertEquals(
        List.of("redis-server runs=false", "redis-server runs=false", "redis-server runs=true"),
        LOG);
    assertInstanceOf(RadiantCore.class, CORES.get(0));
    assertInstanceOf(LibertyCore.class, CORES.get(1));
  }

  /** A team's own annotation, made of {@code @PrimeTest}. */
  @Retention(RetentionPolicy.RUNTIME)
  @PrimeTest(media = {Media.LIBERTY, Media.RADIANT})
  @interface InMemoryMedia {}

  static class WithComposedAnnotation {
    @InMemoryMedia
    void records(PrimeCore core) {
      CORES.add(core);
    }
  }

  @Test
  void anAnnotationMadeOfPrimeTestRunsLikeIt() {
    EngineExecutionResults results = run(WithComposedAnnotation.class);

    assertEquals(List.of("Liberty", "Radiant"), names(results.testEvents().succeeded()));
    assertEquals(2, CORES.size());
  }

  // ------------------------------------------------------------------ setup

  static final class SmallRetention implements CoreSetup {
    private SmallRetention() {}

    @Override
    public void configure(Media media, CoreConfig.Builder config) {
      LOG.add("configure " + media);
      config.name("robot").sourceRetention(7);
    }

    @Override
    public PrimeCore optimus(CoreConfig config, String redisUrl) {
      LOG.add("optimus " + redisUrl);
      return OptimusCore.builder().config(config).redis(redisUrl).queueLimit(3).build();
    }
  }

  static class WithSetup {
    @PrimeTest(media = {Media.RADIANT, Media.OPTIMUS}, setup = SmallRetention.class)
    void configured(PrimeCore core) {
      CORES.add(core);
    }
  }

  @Test
  void theSetupConfiguresEveryCoreAndMakesTheOptimusOneOnTheClasssRedis() {
    EngineExecutionResults results = run(WithSetup.class);

    results.testEvents().assertStatistics(s -> s.started(2).succeeded(2));
    assertEquals(7, CORES.get(0).config().sourceRetention());
    assertEquals(7, CORES.get(1).config().sourceRetention());
    assertTrue(CORES.get(0).name().matches("robot-radiant-\\d+-[0-9a-z]{1,4}"), CORES.get(0).name());
    assertTrue(CORES.get(1).name().matches("robot-optimus-\\d+-[0-9a-z]{1,4}"), CORES.get(1).name());
    OptimusCore optimus = assertInstanceOf(OptimusCore.class, CORES.get(1));
    assertEquals(
        List.of("configure RADIANT", "configure OPTIMUS", "optimus redis://127.0.0.1:" + port(optimus)),
        LOG);
  }

  static final class IgnoresTheConfig implements CoreSetup {
    @Override
    public PrimeCore optimus(CoreConfig config, String redisUrl) {
      PrimeCore made =
          OptimusCore.builder().config(CoreConfig.builder().name("fixed").build()).redis(redisUrl).build();
      REFUSED.add(made);
      return made;
    }
  }

  static class SetupIgnoringTheConfig {
    @PrimeTest(media = Media.OPTIMUS, setup = IgnoresTheConfig.class)
    void runs(PrimeCore core) {
      CORES.add(core);
    }
  }

  @Test
  void anOptimusSetupThatIgnoresTheRunsNameIsRefusedBecauseRunsWouldShareRedisKeys() {
    EngineExecutionResults results = run(SetupIgnoringTheConfig.class);

    String message = failure(results.testEvents().failed().list().get(0)).getMessage();
    assertTrue(message.contains("must make the core with the config it is given"), message);
    assertTrue(message.contains("a core named 'fixed'"), message);
    assertEquals(List.of(), CORES);
    assertEquals(1, REFUSED.size());
    assertTrue(REFUSED.get(0).isClosed(), "the refused core is closed, its connections with it");
  }

  static final class NoPlainConstructor implements CoreSetup {
    NoPlainConstructor(int retention) {}
  }

  static class SetupWithoutPlainConstructor {
    @PrimeTest(setup = NoPlainConstructor.class)
    void runs(PrimeCore core) {}
  }

  @Test
  void aSetupClassWithoutAPlainConstructorIsAClearError() {
    EngineExecutionResults results = run(SetupWithoutPlainConstructor.class);

    results.testEvents().assertStatistics(s -> s.started(0));
    String message = failure(results.containerEvents().failed().list().get(0)).getMessage();
    assertTrue(message.contains("NoPlainConstructor has no constructor without parameters"), message);
  }

  /** Records every instance JUnit's runs make and which of its methods each run called. */
  static final class CountsItsInstances implements CoreSetup {
    private CountsItsInstances() {}

    @Override
    public void configure(Media media, CoreConfig.Builder config) {
      LOG.add("configure " + media + " on setup " + System.identityHashCode(this));
    }

    @Override
    public PrimeCore optimus(CoreConfig config, String redisUrl) {
      LOG.add("optimus on setup " + System.identityHashCode(this));
      return CoreSetup.super.optimus(config, redisUrl);
    }
  }

  static class WithACountedSetup {
    @PrimeTest(setup = CountsItsInstances.class)
    void runs(PrimeCore core) {
      CORES.add(core);
    }
  }

  @Test
  void theSetupIsMadeOncePerRun() {
    EngineExecutionResults results = run(WithACountedSetup.class);

    results.testEvents().assertStatistics(s -> s.started(3).succeeded(3));
    assertEquals(4, LOG.size(), LOG.toString());
    List<String> instances = LOG.stream().map(line -> line.substring(line.lastIndexOf(' ') + 1)).toList();
    assertEquals(3, instances.stream().distinct().count(), "one setup per run: " + LOG);
    assertEquals(instances.get(2), instances.get(3), "the Optimus run's setup configures and makes its core: " + LOG);
    assertTrue(LOG.get(0).startsWith("configure LIBERTY"), LOG.toString());
    assertTrue(LOG.get(2).startsWith("configure OPTIMUS"), LOG.toString());
  }

  abstract static class AbstractSetup implements CoreSetup {}

  static class WithAnAbstractSetup {
    @PrimeTest(setup = AbstractSetup.class)
    void runs(PrimeCore core) {}
  }

  final class InnerSetup implements CoreSetup {}

  static class WithAnInnerSetup {
    @PrimeTest(setup = InnerSetup.class)
    void runs(PrimeCore core) {}
  }

  static final class ThrowingSetup implements CoreSetup {
    ThrowingSetup() {
      throw new IllegalStateException("no robot configured");
    }
  }

  static class WithAThrowingSetup {
    @PrimeTest(media = Media.LIBERTY, setup = ThrowingSetup.class)
    void runs(PrimeCore core) {}
  }

  @Test
  void aSetupClassThatCannotBeMadeIsAClearError() {
    String abstractSetup =
        failure(run(WithAnAbstractSetup.class).containerEvents().failed().list().get(0)).getMessage();
    assertTrue(abstractSetup.contains("@PrimeTest(setup = AbstractSetup.class) on runs()"), abstractSetup);
    assertTrue(abstractSetup.contains("AbstractSetup is abstract; name a concrete class implementing CoreSetup"), abstractSetup);

    String inner =
        failure(run(WithAnInnerSetup.class).containerEvents().failed().list().get(0)).getMessage();
    assertTrue(inner.contains("InnerSetup is an inner class; make it static"), inner);

    String throwing =
        failure(run(WithAThrowingSetup.class).testEvents().failed().list().get(0)).getMessage();
    assertTrue(throwing.contains("the constructor of " + ThrowingSetup.class.getName() + " threw"), throwing);
    assertTrue(throwing.contains("no robot configured"), throwing);
  }

  static final class LongName implements CoreSetup {
    @Override
    public void configure(Media media, CoreConfig.Builder config) {
      config.name("r".repeat(64));
    }
  }

  static class WithALongName {
    @PrimeTest(media = Media.LIBERTY, setup = LongName.class)
    void runs(PrimeCore core) {
      CORES.add(core);
    }
  }

  @Test
  void aNameTooLongForTheRunsSuffixIsCutToTheLongestCoreName() {
    EngineExecutionResults results = run(WithALongName.class);

    results.testEvents().assertStatistics(s -> s.started(1).succeeded(1));
    String name = CORES.get(0).name();
    assertEquals(64, name.length(), name);
    assertTrue(name.matches("r+-liberty-\\d+-[0-9a-z]{1,4}"), name);
  }

  static class NoMedia {
    @PrimeTest(media = {})
    void never(PrimeCore core) {}
  }

  @Test
  void anEmptyListOfMediaIsAClearError() {
    EngineExecutionResults results = run(NoMedia.class);

    String message = failure(results.containerEvents().failed().list().get(0)).getMessage();
    assertTrue(message.contains("names no media, so the test would never run"), message);
  }

  // ------------------------------------------------------------------ injection

  static class Lifecycle {
    private PrimeCore before;

    @BeforeEach
    void before(PrimeCore core) {
      before = core;
      LOG.add("before closed=" + core.isClosed());
    }

    @PrimeTest(media = {Media.LIBERTY, Media.OPTIMUS})
    void test(PrimeCore core) {
      LOG.add("test same=" + (core == before));
    }

    @AfterEach
    void after(PrimeCore core) {
      LOG.add("after same=" + (core == before) + " closed=" + core.isClosed());
      CORES.add(core);
    }
  }

  @Test
  void beforeEachTestAndAfterEachGetTheSameOpenCoreWhichIsClosedAfterwards() {
    EngineExecutionResults results = run(Lifecycle.class);

    results.testEvents().assertStatistics(s -> s.started(2).succeeded(2));
    List<String> oneRun = List.of("before closed=false", "test same=true", "after same=true closed=false");
    assertEquals(
        Stream.concat(oneRun.stream(), oneRun.stream()).toList(), LOG);
    assertNotEquals(CORES.get(0), CORES.get(1));
    assertTrue(CORES.stream().allMatch(PrimeCore::isClosed));
  }

  static class AsksForAReader {
    @PrimeTest(media = Media.LIBERTY)
    void reads(Reader<String> reader) {}
  }

  @Test
  void aParameterTheExtensionCannotInjectIsAClearError() {
    EngineExecutionResults results = run(AsksForAReader.class);

    String message = failure(results.testEvents().failed().list().get(0)).getMessage();
    assertTrue(message.contains("@PrimeTest cannot inject parameter 'dev.prime.Reader<java.lang.String>"), message);
    assertTrue(message.contains("AsksForAReader.reads()"), message);
    assertTrue(message.contains("Make a Reader from the core in the test"), message);
  }

  static class AsksForALibertyCore {
    @PrimeTest(media = {Media.LIBERTY, Media.RADIANT})
    void runs(LibertyCore core) {
      CORES.add(core);
    }
  }

  @Test
  void aMediasOwnCoreTypeIsInjectedOnThatMediaAndRefusedClearlyOnTheOthers() {
    EngineExecutionResults results = run(AsksForALibertyCore.class);

    assertEquals(List.of("Liberty"), names(results.testEvents().succeeded()));
    Event radiant = results.testEvents().failed().list().get(0);
    assertEquals("Radiant", radiant.getTestDescriptor().getDisplayName());
    String message = failure(radiant).getMessage();
    assertTrue(message.contains("it wants a LibertyCore, and this run's core is a RadiantCore"), message);
    assertTrue(message.contains("Declare the parameter as PrimeCore"), message);
    assertEquals(1, CORES.size());
  }

  // ------------------------------------------------------------------ Redis

  @TestMethodOrder(MethodOrderer.OrderAnnotation.class)
  static class TwoOptimusRuns {
    @PrimeTest(media = Media.OPTIMUS)
    @Order(1)
    void publishes(PrimeCore core) throws InterruptedException {
      EventBlock<String> sensor = new EventBlock<>();
      Reader<String> reader = core.source("shared", sensor).reader();
      core.start();
      sensor.publish("first run's value");
      assertEquals("first run's value", reader.take(Duration.ofSeconds(10)).orElseThrow());
      LOG.add(String.valueOf(port((OptimusCore) core)));
    }

    @PrimeTest(media = Media.OPTIMUS)
    @Order(2)
    void seesNothingOfTheFirst(PrimeCore core) throws InterruptedException {
      Reader<String> reader = core.source("shared", new EventBlock<String>()).reader();
      core.start();
      // a reader sees the values its source retains: the first run's, had the runs one namespace
      ReaderAssert.assertThat(reader).emitsNothingWithin(Duration.ofMillis(300));
      LOG.add(String.valueOf(port((OptimusCore) core)));
    }
  }

  @Test
  void optimusRunsOfAClassShareOneRedisInNamespacesOfTheirOwnAndItStopsAfterTheClass()
      throws IOException {
    EngineExecutionResults results = run(TwoOptimusRuns.class);

    results.testEvents().assertStatistics(s -> s.started(2).succeeded(2));
    assertEquals(2, LOG.size());
    assertEquals(LOG.get(0), LOG.get(1), "one Redis for the class");
    int port = Integer.parseInt(LOG.get(0));
    try (Socket socket = new Socket()) {
      socket.connect(new InetSocketAddress("127.0.0.1", port), 2000);
      throw new AssertionError("the class's redis-server still listens on port " + port);
    } catch (ConnectException expected) {
      // stopped after the class
    }
  }

  @Test
  void theRedisOfTheConfigurationParameterIsUsedAndLeftRunning() {
    String url;
    try (EmbeddedRedis redis = EmbeddedRedis.start()) {
      url = redis.getUri();
      EngineExecutionResults results =
          EngineTestKit.engine("junit-jupiter")
              .configurationParameter("prime.test.redis", url)
              .selectors(selectClass(OnEveryMedia.class))
              .execute();

      results.testEvents().assertStatistics(s -> s.succeeded(3));
      assertEquals(redis.getPort(), port((OptimusCore) CORES.get(2)));
      assertTrue(redis.isRunning(), "a Redis the extension did not start is not stopped");
    }
  }

  static class UsesRedis {
    static String url;

    @PrimeTest(media = Media.OPTIMUS)
    void passes(PrimeCore core) throws InterruptedException {
      publishAndRead(core);
    }

    @PrimeTest(media = Media.OPTIMUS)
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
  void anOptimusRunsRedisKeysAreDeletedAfterItWhetherItPassedOrFailed() {
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        Jedis jedis = new Jedis(URI.create(redis.getUri()))) {
      jedis.set("someone-elses-key", "kept");
      UsesRedis.url = redis.getUri();
      EngineExecutionResults results =
          EngineTestKit.engine("junit-jupiter")
              .configurationParameter("prime.test.redis", redis.getUri())
              .selectors(selectClass(UsesRedis.class))
              .execute();

      results.testEvents().assertStatistics(s -> s.succeeded(1).failed(1));
      assertEquals(2, LOG.size(), LOG.toString());
      KeyLeavingRun.assertEveryRunHadKeysAndLeftNone(LOG, CORES, redis.getUri());
      assertEquals(Set.of("someone-elses-key"), jedis.keys("*"), "only the key that was not a run's is left");
    }
  }

  static class LeavesASecondCoreOpen {
    static final List<PrimeCore> LEFT_OPEN = new CopyOnWriteArrayList<>();

    @PrimeTest(media = Media.OPTIMUS)
    void passes(PrimeCore core) {
      OptimusCore second =
          OptimusCore.builder()
              .config(CoreConfig.builder().name(core.name()).build())
              .redis(((OptimusCore) core).getRedisUrl())
              .hosts(List.of())
              .build();
      LEFT_OPEN.add(second);
      second.source("numbers", new EventBlock<Integer>()).reader();
      second.start();
    }
  }

  @Test
  void anOptimusRunWhoseKeysCannotBeDeletedBecauseAnotherCoreOfItsNameIsOpenFails() {
    try {
      EngineExecutionResults results = run(LeavesASecondCoreOpen.class);
      results.testEvents().assertStatistics(s -> s.failed(1));
      Throwable thrown =
          results.testEvents().failed().stream().findFirst().orElseThrow()
              .getPayload(TestExecutionResult.class).orElseThrow().getThrowable().orElseThrow();
      assertInstanceOf(IllegalStateException.class, thrown);
      assertTrue(thrown.getMessage().contains("is still run by 1 other process(es)"), thrown.getMessage());
    } finally {
      LeavesASecondCoreOpen.LEFT_OPEN.forEach(PrimeCore::close);
      LeavesASecondCoreOpen.LEFT_OPEN.clear();
    }
  }

  static class LosesItsRedis {
    static EmbeddedRedis redis;

    @PrimeTest(media = Media.OPTIMUS)
    void passes(PrimeCore core) {
      core.source("numbers", new EventBlock<Integer>()).reader();
      core.start();
      redis.close(); // gone for good: the run's keys cannot be deleted after it
    }
  }

  /**
   * PrimeTest: the run fails with a RedisUnavailableException if Redis cannot be reached for 10 s
   * when its keys are deleted.
   */
  @Test
  void anOptimusRunWhoseKeysCannotBeDeletedBecauseRedisIsGoneFailsWithRedisUnavailable() {
    try (EmbeddedRedis redis = EmbeddedRedis.start()) {
      LosesItsRedis.redis = redis;
      long began = System.nanoTime();
      EngineExecutionResults results =
          EngineTestKit.engine("junit-jupiter")
              .configurationParameter("prime.test.redis", redis.getUri())
              .selectors(selectClass(LosesItsRedis.class))
              .execute();
      long seconds = Duration.ofNanos(System.nanoTime() - began).toSeconds();

      results.testEvents().assertStatistics(s -> s.failed(1));
      Throwable thrown = failure(results.testEvents().failed().stream().findFirst().orElseThrow());
      assertInstanceOf(RedisUnavailableException.class, thrown, "the run's failure: " + thrown);
      assertTrue(seconds >= 9, "it tried for about 10 s, not " + seconds + " s");
    } finally {
      LosesItsRedis.redis = null;
    }
  }

  // ------------------------------------------------------------------ helpers

  static EngineExecutionResults run(Class<?> testClass) {
    return EngineTestKit.engine("junit-jupiter").selectors(selectClass(testClass)).execute();
  }

  static List<String> names(Events events) {
    return events.stream().map(e -> e.getTestDescriptor().getDisplayName()).toList();
  }

  private static String names(List<PrimeCore> cores) {
    return cores.stream().map(PrimeCore::name).toList().toString();
  }

  static int port(OptimusCore core) {
    return URI.create(core.getRedisUrl()).getPort();
  }

  static Throwable failure(Event event) {
    return event.getPayload(TestExecutionResult.class).orElseThrow().getThrowable().orElseThrow();
  }
}
