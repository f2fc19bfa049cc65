package dev.prime.test.internal;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.test.CoreSetup;
import dev.prime.test.Media;
import java.util.function.Supplier;
import org.junit.jupiter.api.extension.ExtensionConfigurationException;

/**
 * The lookup of the media: checks that a media's module is on the class path before anything
 * touches its classes, then makes its core through the one class that names them.
 */
public final class MediaCores {
  private MediaCores() {}

  /**
   * Makes a core of {@code media}.
   *
   * @param media the media
   * @param config the settings, already named
   * @param setup makes the Optimus core
   * @param redisUrl the Redis for Optimus (on the slow link, its proxy), asked for only on Optimus
   * @return a new core, not started
   * @throws ExtensionConfigurationException if the media's module is not on the class path
   */
  static PrimeCore create(
      Media media, CoreConfig config, CoreSetup setup, Supplier<String> redisUrl) {
    requireOnClassPath(media);
    try {
      return switch (media) {
        case LIBERTY -> LibertyCores.create(config);
        case RADIANT -> RadiantCores.create(config);
        case OPTIMUS, OPTIMUS_SLOW_LINK -> setup.optimus(config, redisUrl.get());
      };
    } catch (NoClassDefFoundError e) {
      throw new ExtensionConfigurationException(
          media.displayName() + " needs a class that is not on the test class path ("
              + e.getMessage() + "); add " + media.module() + " with its own dependencies (a"
              + " dependency manager adds them when the module is declared, not copied as a jar)",
          e);
    }
  }

  /**
   * The default of {@link CoreSetup#optimus}.
   *
   * @param config the settings
   * @param redisUrl the Redis
   * @return a new Optimus core on that Redis
   */
  public static PrimeCore defaultOptimus(CoreConfig config, String redisUrl) {
    requireOnClassPath(Media.OPTIMUS);
    return OptimusCores.create(config, redisUrl);
  }

  /**
   * Deletes the Redis keys of a closed Optimus core (its name is its run's own, so nothing else
   * uses them); nothing on the other media, which keep nothing outside the JVM.
   *
   * @param media the media of the run
   * @param core the run's core, closed
   */
  static void deleteKeys(Media media, PrimeCore core) {
    if (media == Media.OPTIMUS || media == Media.OPTIMUS_SLOW_LINK) {
      OptimusCores.deleteKeys(core);
    }
  }

  /** Starts an embedded redis-server for a test class. */
  static SharedRedis startEmbeddedRedis() {
    requireOnClassPath(Media.OPTIMUS);
    return OptimusCores.startEmbeddedRedis();
  }

  private static void requireOnClassPath(Media media) {
    if (!media.isOnClassPath()) {
      throw new ExtensionConfigurationException(
          "@PrimeTest runs this test on " + media.displayName() + ", but " + media.module()
              + " is not on the test class path (there is no class " + media.coreClassName()
              + "). Add the test dependency " + media.module()
              + " (Maven: <scope>test</scope>; Gradle: testImplementation), or leave "
              + media.displayName() + " out: @PrimeTest(media = {...}) without " + media.name()
              + ".");
    }
  }
}
