package dev.prime.metrics;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.optimus.OptimusCore;

/** The binder on Optimus, each core on an embedded Redis of its own (a real redis-server). */
class OptimusPrimeMetricsTest extends PrimeMetricsContract {
  @Override
  PrimeCore newCore(CoreConfig config) {
    return OptimusCore.builder().config(config).build();
  }

  @Override
  String media() {
    return "optimus";
  }

  @Override
  boolean deadLetters() {
    return true;
  }

  @Override
  boolean chainsHaveQueues() {
    return true;
  }
}
