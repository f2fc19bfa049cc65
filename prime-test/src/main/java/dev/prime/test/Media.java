package dev.prime.test;

/**
 * The media a {@link PrimeTest} runs on. Each needs its module on the test class path: {@code
 * dev.prime:prime-liberty}, {@code dev.prime:prime-radiant} or {@code dev.prime:prime-optimus}
 * (for {@link #OPTIMUS} and {@link #OPTIMUS_SLOW_LINK}).
 */
public enum Media {
  /** {@code LibertyCore}: chains fused by function composition, in-memory sources. */
  LIBERTY("Liberty", "dev.prime.liberty.LibertyCore", "prime-liberty"),
  /** {@code RadiantCore}: one generated class per linked chain, in-memory sources. */
  RADIANT("Radiant", "dev.prime.radiant.RadiantCore", "prime-radiant"),
  /**
   * {@code OptimusCore}: every chain a service over Redis lists, on a Redis shared by the test
   * class (an embedded {@code redis-server} unless the JUnit configuration parameter {@code
   * prime.test.redis} names one).
   */
  OPTIMUS("Optimus", "dev.prime.optimus.OptimusCore", "prime-optimus"),
  /**
   * {@code OptimusCore} as on {@link #OPTIMUS}, with the test class's Redis reached over a slow
   * network link: a proxy on the loopback interface, one per test class and closed with it, holds
   * every byte back by a delay in each direction, so each round trip to Redis takes twice the
   * delay longer, as over Wi-Fi or across a data centre. Run a test on it next to {@link
   * #OPTIMUS} to find what depends on Redis answering at once: races between services, timeouts
   * too short for a remote Redis.
   *
   * <p>Not among {@link PrimeTest#media()}'s defaults: name it, {@code @PrimeTest(media = {OPTIMUS,
   * OPTIMUS_SLOW_LINK})}. The delay is the JUnit configuration parameter {@code
   * prime.test.slowLink.delay}: milliseconds followed by {@code ms}, up to six decimals, from
   * {@code 0ms} to {@code 10000ms} ({@code prime.test.slowLink.delay=5ms} in {@code
   * junit-platform.properties}, or a system property of the test JVM); unset, {@code 1ms}. Any
   * other value fails the run with a message naming the parameter. Each byte the core sends
   * reaches Redis that long after the proxy read it, and each byte Redis sends reaches the core
   * that long after; bytes read together arrive together (the link adds latency, it does not
   * limit bandwidth), and opening a connection adds no delay of its own.
   *
   * <p>The proxy fronts the class's Redis: the embedded {@code redis-server}, or the Redis of
   * {@code prime.test.redis}, which must then be a {@code redis://} URL of one server (a TLS
   * Redis's certificate would be checked against the proxy's address, and a Redis Cluster's core
   * reaches the nodes past the proxy; the run fails saying so). {@link CoreSetup#optimus} makes
   * the core, given the proxy's URL (the Redis's, with the proxy's address and port); {@link
   * CoreSetup#configure} is given this media. The run's Redis keys are deleted after it, as on
   * {@link #OPTIMUS}.
   */
  OPTIMUS_SLOW_LINK("Optimus, slow link", "dev.prime.optimus.OptimusCore", "prime-optimus");

  private final String displayName;
  private final String coreClass;
  private final String artifactId;

  Media(String displayName, String coreClass, String artifactId) {
    this.displayName = displayName;
    this.coreClass = coreClass;
    this.artifactId = artifactId;
  }

  /**
   * {@return the name shown in test reports: {@code Liberty}, {@code Radiant}, {@code Optimus},
   * {@code Optimus, slow link}}
   */
  public String displayName() {
    return displayName;
  }

  /** {@return the Maven coordinates of the media's module, {@code dev.prime:prime-liberty}, ...} */
  public String module() {
    return "dev.prime:" + artifactId;
  }

  /** {@return the fully qualified name of the media's core class} */
  public String coreClassName() {
    return coreClass;
  }

  /**
   * {@return whether the media's module is on the class path of this library}
   */
  public boolean isOnClassPath() {
    try {
      Class.forName(coreClass, false, Media.class.getClassLoader());
      return true;
    } catch (ClassNotFoundException | LinkageError e) {
      return false;
    }
  }
}
