package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import dev.prime.optimus.OptimusCore;
import dev.prime.radiant.RadiantCore;
import java.util.Arrays;
import java.util.Collection;
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
  /**
   * Every chain a service over Redis lists, on an embedded Redis of the core's own (see {@link
   * #optimus} for a shared Redis and services in other processes).
   */
  OPTIMUS("optimus", config -> optimus(config, null, null)),
  ;

  private final String cliName;
  private final Function<CoreConfig, PrimeCore> factory;

  Media(String cliName, Function<CoreConfig, PrimeCore> factory) {
    this.cliName = cliName;
    this.factory = factory;
  }

  /** {@return the name used on the command line} */
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
   * An Optimus core for the robot, its codec knowing {@link RobotTypes}.
   *
   * @param config the core's settings; processes that share a topology use the same name
   * @param redisUrl the Redis to use, or {@code null} for an embedded one owned by the core
   * @param hosts the services this process runs, or {@code null} for all of them
   * @return a new core, not started
   * @throws IllegalArgumentException if the URL is malformed
   * @throws dev.prime.PrimeException if the Redis cannot be reached
   */
  public static OptimusCore optimus(
      CoreConfig config, String redisUrl, Collection<String> hosts) {
    OptimusCore.Builder builder = OptimusCore.builder().config(config).codec(RobotTypes.codec());
    if (redisUrl != null) {
      builder.redis(redisUrl);
    }
    if (hosts != null) {
      builder.hosts(hosts);
    }
    return builder.build();
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

  /** {@return the command-line names of every media, separated by commas} */
  public static String knownNames() {
    return Arrays.stream(values()).map(Media::cliName).collect(Collectors.joining(", "));
  }
}
