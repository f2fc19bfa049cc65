package dev.prime.test.internal;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;

/** Makes Liberty cores; loaded only once prime-liberty is known to be on the class path. */
final class LibertyCores {
  private LibertyCores() {}

  static PrimeCore create(CoreConfig config) {
    return new LibertyCore(config);
  }
}
