package dev.prime.examples.fusion;

import dev.prime.Block;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.Tick;
import dev.prime.Tuple2;
import dev.prime.VirtualClock;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;

/**
 * A line follower's sensor fusion with Prime's combinators: a gyro read at 100 Hz and a line
 * sensor read at 20 Hz, each driven by a timer of the core's clock; every gyro reading is fused
 * with the latest line reading ({@code withLatestFrom}) and a PD steering controller turns the
 * pair into a turn rate. The sensors are simulated from the time of their tick (the robot weaves
 * around the line), so the whole controller runs on a {@link VirtualClock}, as fast as the
 * machine allows, with the same ticks every run. The README shows the declaration between the fusion
 * markers; a test checks that it is this code.
 */
public final class LineFollower {

  /** The gyro's period: 100 Hz. */
  public static final Duration GYRO_PERIOD = Duration.ofMillis(10);

  /** The line sensor's period: 20 Hz. */
  public static final Duration LINE_PERIOD = Duration.ofMillis(50);

  private LineFollower() {}

  /**
   * A gyro reading.
   *
   * @param millis when it was taken, in milliseconds of the core's clock since start
   * @param yawRate how fast the robot turns, rad/s, positive to the left
   */
  public record GyroReading(long millis, double yawRate) {}

  /**
   * A line-sensor reading.
   *
   * @param millis when it was taken, in milliseconds of the core's clock since start
   * @param offset where the line is, metres, positive to the left of the robot's centre
   */
  public record LineReading(long millis, double offset) {}

  /**
   * A steering command.
   *
   * @param gyroMillis the time of the gyro reading it was made from
   * @param lineMillis the time of the line reading it was made from
   * @param turnRate the turn rate to command, rad/s, positive to the left
   */
  public record Steering(long gyroMillis, long lineMillis, double turnRate) {}

  /** The simulated gyro: the robot weaves, turning with 0.5 rad/s * cos(t). */
  public static final class Gyro implements Block<Tick, GyroReading> {
    @Override
    public GyroReading process(Tick tick) {
      long millis = tick.count() * GYRO_PERIOD.toMillis();
      return new GyroReading(millis, 0.5 * Math.cos(millis / 1000.0));
    }
  }

  /** The simulated line sensor: the line is 0.1 m * sin(t) to the left. */
  public static final class LineSensor implements Block<Tick, LineReading> {
    @Override
    public LineReading process(Tick tick) {
      long millis = tick.count() * LINE_PERIOD.toMillis();
      return new LineReading(millis, 0.1 * Math.sin(millis / 1000.0));
    }
  }

  /**
   * A PD steering controller: turn towards the line, damped by the measured yaw rate.
   *
   * @param kp gain on the line offset, rad/s per metre
   * @param kd gain on the yaw rate
   */
  public record SteeringController(double kp, double kd)
      implements Block<Tuple2<GyroReading, LineReading>, Steering> {
    @Override
    public Steering process(Tuple2<GyroReading, LineReading> fused) {
      GyroReading gyro = fused.first();
      LineReading line = fused.second();
      return new Steering(
          gyro.millis(), line.millis(), kp * line.offset() - kd * gyro.yawRate());
    }
  }

  /**
   * Declares the line follower on {@code core}, starts it and steps {@code clock} one gyro period
   * at a time for {@code duration}, collecting the steering commands.
   *
   * @param core a new core whose {@code CoreConfig.clock} is {@code clock}
   * @param clock the core's virtual clock
   * @param duration how much virtual time to run
   * @return the steering commands, in order
   * @throws InterruptedException if interrupted while waiting for a command
   */
  public static List<Steering> run(PrimeCore core, VirtualClock clock, Duration duration)
      throws InterruptedException {
    // fusion:begin
    Source<GyroReading> gyro =
        core.timer("gyro-clock", Duration.ofMillis(10))                 // 100 Hz
            .then(core.chain("gyro", new Gyro()));
    Source<LineReading> line =
        core.timer("line-clock", Duration.ofMillis(50))                 // 20 Hz
            .then(core.chain("line", new LineSensor()));
    Source<Steering> steering =
        gyro.withLatestFrom(line)                 // each gyro reading + the latest line reading
            .then(core.chain("steer", new SteeringController(2.0, 0.3)));
    // fusion:end
    Reader<Steering> commands = steering.reader();
    core.start();
    List<Steering> out = new ArrayList<>();
    long steps = duration.dividedBy(GYRO_PERIOD);
    for (long step = 1; step <= steps; step++) {
      clock.advance(GYRO_PERIOD);
      // Before the first line reading the gyro's readings have nothing to fuse with and are
      // dropped; after it, every gyro reading gives one command: wait for it, so the virtual
      // clock never runs ahead of the controller.
      if (out.isEmpty()) {
        commands.take(Duration.ofMillis(20)).ifPresent(out::add);
      }
      long now = step * GYRO_PERIOD.toMillis();
      while (!out.isEmpty() && out.get(out.size() - 1).gyroMillis() < now) {
        long due = now;
        out.add(
            commands
                .take(PATIENCE)
                .orElseThrow(() -> new IllegalStateException("no steering command at " + due + " ms")));
      }
    }
    return out;
  }

  private static final Duration PATIENCE = Duration.ofSeconds(20);
}
