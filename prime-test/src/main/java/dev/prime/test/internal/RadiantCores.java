package dev.prime.test.internal;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.radiant.RadiantCore;

/** Makes Radiant cores; loaded only once prime-radiant is known to be on the class path. */
final class RadiantCores {
  private RadiantCores() {}

  static PrimeCore create(CoreConfig config) {
    return new RadiantCore(config);
  }
}
