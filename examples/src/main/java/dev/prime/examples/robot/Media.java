package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import dev.prime.radiant.RadiantCore;
import java.util.Arrays;
import java.util.Locale;
import java.util.function.Function;
import java.util.stream.Collectors;

/**
 * The media the example can run on, by the name given to {@code --media}. Choosing a media is
 * choosing which core is created; nothing else in the example changes.
 */
public enum Media {
  /** Chains fused by function composition, in-memory sources. */
  LIBERTY("liberty", LibertyCore::new),
  /** Each linked chain fused into one generated class, in-memory sources. */
  RADIANT("radiant", RadiantCore::new),
  // A new media plugs in here with one line (and its module as a dependency in examples/pom.xml):
  //   OPTIMUS("optimus", OptimusCore::new),
  ;

  private final String cliName;
  private final Function<CoreConfig, PrimeCore> factory;

  Media(String cliName, Function<CoreConfig, PrimeCore> factory) {
    this.cliName = cliName;
    this.factory = factory;
  }

  /** The name used on the command line. */
  public String cliName() {
    return cliName;
  }

  /**
   * Creates a core of this media.
   *
   * @param config the core's settings
   * @return a new core, not started
   */
  public PrimeCore create(CoreConfig config) {
    return factory.apply(config);
  }

  /**
   * The media with a command-line name.
   *
   * @param name a name such as {@code liberty}; case does not matter
   * @return the media
   * @throws IllegalArgumentException if no media has that name; the message lists the known ones
   */
  public static Media byName(String name) {
    String wanted = name.toLowerCase(Locale.ROOT);
    for (Media media : values()) {
      if (media.cliName.equals(wanted)) {
        return media;
      }
    }
    throw new IllegalArgumentException(
        "unknown media '" + name + "'; known media: " + knownNames());
  }

  /** The command-line names of every media, separated by commas. */
  public static String knownNames() {
    return Arrays.stream(values()).map(Media::cliName).collect(Collectors.joining(", "));
  }
}
