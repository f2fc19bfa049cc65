package dev.prime.liberty;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.conformance.MediaConformance;

/** Runs the whole media conformance kit against Liberty. */
class LibertyConformanceTest implements MediaConformance {

  @Override
  public PrimeCore newCore(CoreConfig config) {
    return new LibertyCore(config);
  }
}
