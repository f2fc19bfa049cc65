package dev.prime.examples.robot;

import dev.prime.optimus.KryoCodec;
import java.util.List;

/**
 * The robot's types that cross Redis on the Optimus media, allowed by every process of a topology
 * spread over several (the processes must agree, which the codec's fingerprint checks; the order
 * does not matter). A type added to a chain's input or output, or nested in one, is added here.
 * One process alone needs none of this: a plain {@code new OptimusCore()} carries the robot's
 * records.
 */
public final class RobotTypes {

  /** Every type a chain or source of the robot carries, nested types included. */
  public static final List<Class<?>> ALL =
      List.of(
          EncoderReading.class,
          Pose.class,
          WheelSpeeds.class,
          Estimate.class,
          Setpoint.class,
          DriveCommand.class);

  private RobotTypes() {}

  /** {@return A codec that allows every type of {@link #ALL}} */
  public static KryoCodec codec() {
    KryoCodec.Builder builder = KryoCodec.builder();
    for (Class<?> type : ALL) {
      builder.allow(type);
    }
    return builder.build();
  }
}
