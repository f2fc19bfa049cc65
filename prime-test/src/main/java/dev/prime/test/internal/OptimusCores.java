package dev.prime.test.internal;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.OptimusCore;

/** Makes Optimus cores and embedded Redis servers; loaded only once prime-optimus is known to be on the class path. */
final class OptimusCores {
  private OptimusCores() {}

  static PrimeCore create(CoreConfig config, String redisUrl) {
    return OptimusCore.builder().config(config).redis(redisUrl).build();
  }

  /** Deletes the keys of {@code core}, closed, if it is an Optimus core (a setup may make another). */
  static void deleteKeys(PrimeCore core) {
    if (core instanceof OptimusCore optimus) {
      optimus.deleteKeys();
    }
  }

  static SharedRedis startEmbeddedRedis() {
    EmbeddedRedis server = EmbeddedRedis.start();
    return new SharedRedis(server.getUri(), server::close);
  }
}
