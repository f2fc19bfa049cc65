package dev.prime.test;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.optimus.OptimusCore;
import java.net.URI;
import java.time.Duration;

/**
 * A test class with an Optimus run and a run over the slow link, for {@link ClassEndCleanupTest},
 * which runs it through a JUnit launcher (perhaps in a class loader of its own, with another
 * JUnit): each run leaves the port its core talks to (the class's redis-server, the slow link's
 * proxy) in a system property, which every class loader sees.
 */
final class ClassEndCleanupRun {
  /** The system property of the Optimus run's Redis port. */
  static final String REDIS_PORT = "prime.test.cleanupRun.redisPort";

  /** The system property of the slow link run's proxy port. */
  static final String LINK_PORT = "prime.test.cleanupRun.linkPort";

  @PrimeTest(media = Media.OPTIMUS)
  void onOptimus(PrimeCore core) throws InterruptedException {
    System.setProperty(REDIS_PORT, String.valueOf(publishAndRead(core)));
  }

  @PrimeTest(media = Media.OPTIMUS_SLOW_LINK)
  void overTheSlowLink(PrimeCore core) throws InterruptedException {
    System.setProperty(LINK_PORT, String.valueOf(publishAndRead(core)));
  }

  /** Publishes a value and reads it back; returns the port of the Redis URL the core uses. */
  private static int publishAndRead(PrimeCore core) throws InterruptedException {
    EventBlock<String> sensor = new EventBlock<>();
    Reader<String> reader = core.source("sensor", sensor).reader();
    core.start();
    sensor.publish("value");
    assertEquals("value", reader.take(Duration.ofSeconds(20)).orElseThrow());
    return URI.create(((OptimusCore) core).getRedisUrl()).getPort();
  }
}
