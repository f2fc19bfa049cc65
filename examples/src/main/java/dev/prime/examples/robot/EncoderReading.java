package dev.prime.examples.robot;

/**
 * What the wheel encoders count at one step: the total ticks of each wheel since power-on.
 *
 * @param step the simulation step the counts were sampled at
 * @param leftTicks total ticks of the left wheel (negative when it ran backwards)
 * @param rightTicks total ticks of the right wheel
 */
public record EncoderReading(long step, long leftTicks, long rightTicks) {}
