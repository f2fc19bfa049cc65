package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.test.CoreSetup;
import dev.prime.test.PrimeTest;

/** The robot's cores for {@link PrimeTest}: on Optimus, a codec that knows the robot's types. */
final class RobotCores implements CoreSetup {
  @Override
  public PrimeCore optimus(CoreConfig config, String redisUrl) {
    return Media.optimus(config, redisUrl, null);
  }
}
