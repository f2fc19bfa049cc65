package dev.prime.examples.robot;

import dev.prime.optimus.KryoCodec;
import java.util.List;

/**
 * The robot's types that cross Redis on the Optimus media, in the one order every process
 * registers them (the codec's fingerprint depends on it, and the processes of one topology must
 * agree). A type added to a chain's input or output, or nested in one, is added here, at the end.
 */
public final class RobotTypes {

  /** Every type a chain or source of the robot carries, nested types included, in fixed order. */
  public static final List<Class<?>> ALL =
      List.of(
          EncoderReading.class,
          Pose.class,
          WheelSpeeds.class,
          Estimate.class,
          Setpoint.class,
          DriveCommand.class);

  private RobotTypes() {}

  /** {@return A codec that knows every type of {@link #ALL}, registered in that order} */
  public static KryoCodec codec() {
    KryoCodec.Builder builder = KryoCodec.builder();
    for (Class<?> type : ALL) {
      builder.register(type);
    }
    return builder.build();
  }
}
