package dev.prime.test;

/**
 * The media a {@link PrimeTest} runs on. Each needs its module on the test class path: {@code
 * dev.prime:prime-liberty}, {@code dev.prime:prime-radiant} or {@code dev.prime:prime-optimus}.
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
  OPTIMUS("Optimus", "dev.prime.optimus.OptimusCore", "prime-optimus");

  private final String displayName;
  private final String coreClass;
  private final String artifactId;

  Media(String displayName, String coreClass, String artifactId) {
    this.displayName = displayName;
    this.coreClass = coreClass;
    this.artifactId = artifactId;
  }

  /** {@return the name shown in test reports: {@code Liberty}, {@code Radiant}, {@code Optimus}} */
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
