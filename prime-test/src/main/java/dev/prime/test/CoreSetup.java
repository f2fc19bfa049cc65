package dev.prime.test;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.test.internal.MediaCores;

/**
 * How a {@link PrimeTest} makes the core of each invocation. Implement the methods you need and
 * name the class in {@link PrimeTest#setup()}; it needs a constructor without parameters (it may
 * be private, and the class may be a static nested class of the test).
 *
 * <pre>{@code
 * static final class RobotCores implements CoreSetup {
 *   public void configure(Media media, CoreConfig.Builder config) {
 *     config.sourceRetention(64);
 *   }
 *   public PrimeCore optimus(CoreConfig config, String redisUrl) {
 *     return OptimusCore.builder().config(config).redis(redisUrl).codec(RobotTypes.codec()).build();
 *   }
 * }
 *
 * @PrimeTest(setup = RobotCores.class)
 * void drives(PrimeCore core) { ... }
 * }</pre>
 *
 * <p>One instance is made per invocation.
 */
public interface CoreSetup {

  /**
   * Adjusts the settings of an invocation's core, before the core is made. Whatever name is set
   * here, the extension then gives the core a name of its own, {@code <name>-<media>-<n>-<jvm>}
   * ({@code test-<media>-<n>-<jvm>} if none was set; {@code n} counts the cores of the JVM, {@code
   * jvm} is random per JVM), so that every invocation has its own namespace (on Optimus, its own
   * Redis keys), also on a Redis that several test JVMs share.
   *
   * <p>The default changes nothing.
   *
   * @param media the media of the invocation
   * @param config a builder starting from {@link CoreConfig#defaults()}
   */
  default void configure(Media media, CoreConfig.Builder config) {}

  /**
   * Makes the core of an Optimus invocation; override it to choose a codec, queue limits or call
   * timeouts. The core must use {@code config} (its name is the invocation's namespace) and
   * should use the Redis at {@code redisUrl}.
   *
   * <p>The default is {@code OptimusCore.builder().config(config).redis(redisUrl).build()}.
   *
   * @param config the invocation's settings, named by the extension
   * @param redisUrl the Redis shared by the test class; on {@link Media#OPTIMUS_SLOW_LINK} the
   *     URL of the class's slow link in front of it (the Redis's URL with the proxy's address)
   * @return a new core, not started
   */
  default PrimeCore optimus(CoreConfig config, String redisUrl) {
    return MediaCores.defaultOptimus(config, redisUrl);
  }
}
