package dev.prime.metrics;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;

/** The binder on Liberty. */
class LibertyPrimeMetricsTest extends PrimeMetricsContract {
  @Override
  PrimeCore newCore(CoreConfig config) {
    return new LibertyCore(config);
  }

  @Override
  String media() {
    return "liberty";
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
