package dev.prime.radiant;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.conformance.MediaConformance;

/** Runs the whole media conformance kit against Radiant. */
class RadiantConformanceTest implements MediaConformance {

  @Override
  public PrimeCore newCore(CoreConfig config) {
    return new RadiantCore(config);
  }
}
