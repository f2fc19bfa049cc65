package dev.prime.metrics;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.radiant.RadiantCore;

/** The binder on Radiant. */
class RadiantPrimeMetricsTest extends PrimeMetricsContract {
  @Override
  PrimeCore newCore(CoreConfig config) {
    return new RadiantCore(config);
  }

  @Override
  String media() {
    return "radiant";
  }

  @Override
  boolean deadLetters() {
    return false;
  }

  @Override
  boolean chainsHaveQueues() {
    return false;
  }
}
