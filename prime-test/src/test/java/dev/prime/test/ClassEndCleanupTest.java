package dev.prime.test;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.platform.engine.discovery.DiscoverySelectors.selectClass;

import java.io.File;
import java.io.IOException;
import java.net.ConnectException;
import java.net.InetSocketAddress;
import java.net.Socket;
import java.net.URL;
import java.net.URLClassLoader;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.Callable;
import java.util.stream.Stream;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.Test;
import org.junit.platform.testkit.engine.EngineTestKit;

/**
 * The Redis a test class's Optimus runs share and the slow link in front of it are stopped when
 * the class ends, on every JUnit 5 the extension supports: they are values of the class's
 * extension store, which JUnit closes as {@code CloseableResource}s on every JUnit 5 and as
 * {@code AutoCloseable}s only from 5.13 on, unless that is switched off.
 */
class ClassEndCleanupTest {

  /** The jar names of JUnit itself and what it needs, left out of the older JUnit's class path. */
  private static final List<String> JUNIT_JARS =
      List.of("junit-jupiter", "junit-platform", "opentest4j", "apiguardian");

  @BeforeEach
  void clear() {
    System.clearProperty(ClassEndCleanupRun.REDIS_PORT);
    System.clearProperty(ClassEndCleanupRun.LINK_PORT);
  }

  /** This project's JUnit, with the closing of stored AutoCloseables switched off. */
  @Test
  void theRedisAndTheSlowLinkStopAfterTheClassWhenJUnitClosesNoAutoCloseable() throws IOException {
    EngineTestKit.engine("junit-jupiter")
        .configurationParameter("junit.jupiter.extensions.store.close.autocloseable.enabled", "false")
        .selectors(selectClass(ClassEndCleanupRun.class))
        .execute()
        .testEvents()
        .assertStatistics(s -> s.started(2).succeeded(2));
    assertStoppedAfterTheClass();
  }

  /**
   * The oldest JUnit the extension is tested on (before 5.13: it closes no AutoCloseable), from the
   * jars the build copied, in a class loader of its own over this module's class path without its
   * JUnit: its launcher runs the test class, and its Jupiter engine's version is checked.
   */
  @Test
  void theRedisAndTheSlowLinkStopAfterTheClassOnTheOldestJUnit() throws Exception {
    String version = System.getProperty("prime.test.oldestJUnit.version");
    String dir = System.getProperty("prime.test.oldestJUnit.dir");
    assertNotNull(dir, "the build gives the directory of the oldest JUnit's jars (prime-test's pom)");
    List<URL> path = new ArrayList<>();
    try (Stream<Path> jars = Files.list(Path.of(dir))) {
      for (Path jar : jars.sorted().toList()) {
        path.add(jar.toUri().toURL());
      }
    }
    assertEquals(7, path.size(), "the oldest JUnit's jars in " + dir);
    for (String entry : System.getProperty("java.class.path").split(File.pathSeparator)) {
      String name = Path.of(entry).getFileName().toString();
      if (JUNIT_JARS.stream().noneMatch(name::startsWith)) {
        path.add(Path.of(entry).toUri().toURL());
      }
    }
    String summary;
    Thread thread = Thread.currentThread();
    ClassLoader before = thread.getContextClassLoader();
    try (URLClassLoader oldest =
        new URLClassLoader("junit-" + version, path.toArray(URL[]::new), ClassLoader.getPlatformClassLoader())) {
      thread.setContextClassLoader(oldest); // where the launcher looks for its engines
      @SuppressWarnings("unchecked")
      Callable<String> launch =
          (Callable<String>) oldest.loadClass(OldestJUnitLauncher.class.getName()).getConstructor().newInstance();
      summary = launch.call();
    } finally {
      thread.setContextClassLoader(before);
    }
    assertEquals("Jupiter " + version + ": 2 succeeded, 0 failed", summary);
    assertStoppedAfterTheClass();
  }

  private static void assertStoppedAfterTheClass() throws IOException {
    String redis = System.getProperty(ClassEndCleanupRun.REDIS_PORT);
    String link = System.getProperty(ClassEndCleanupRun.LINK_PORT);
    assertNotNull(redis, "the Optimus run gave its Redis port");
    assertNotNull(link, "the slow link run gave its proxy's port");
    assertRefused(Integer.parseInt(redis), "the class's redis-server");
    assertRefused(Integer.parseInt(link), "the class's slow link");
    assertFalse(
        Thread.getAllStackTraces().keySet().stream()
            .anyMatch(t -> t.getName().equals("prime-test-slow-link-" + link) && t.isAlive()),
        "the slow link's thread prime-test-slow-link-" + link + " still runs after the class");
  }

  private static void assertRefused(int port, String what) throws IOException {
    try (Socket socket = new Socket()) {
      socket.connect(new InetSocketAddress("127.0.0.1", port), 2000);
      throw new AssertionError(what + " still listens on port " + port + " after the class ended");
    } catch (ConnectException expected) {
      // stopped after the class
    }
  }
}
