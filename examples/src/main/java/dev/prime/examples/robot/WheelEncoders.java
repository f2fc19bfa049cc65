package dev.prime.examples.robot;

import dev.prime.EventBlock;
import java.util.Objects;

/**
 * Simulated wheel encoders: count whole ticks of the plant's wheels and publish them as events.
 * Logic layer: the events are a plain {@link EventBlock}; a core turns them into a source.
 */
public final class WheelEncoders {
  private final RobotSpec spec;
  private final EventBlock<EncoderReading> events = new EventBlock<>();

  /**
   * @param spec the robot, for the tick size
   */
  public WheelEncoders(RobotSpec spec) {
    this.spec = Objects.requireNonNull(spec, "spec must not be null");
  }

  /** {@return the readings, one per {@link #sample}} */
  public EventBlock<EncoderReading> events() {
    return events;
  }

  /**
   * Reads the plant's wheels and publishes the counts.
   *
   * @param step the simulation step
   * @param plant the robot
   * @return the published reading
   */
  public EncoderReading sample(long step, DifferentialDrivePlant plant) {
    EncoderReading reading =
        new EncoderReading(step, ticks(plant.leftTravel()), ticks(plant.rightTravel()));
    events.publish(reading);
    return reading;
  }

  private long ticks(double travel) {
    return (long) Math.floor(travel / spec.metresPerTick());
  }
}
