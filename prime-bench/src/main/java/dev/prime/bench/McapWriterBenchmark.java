package dev.prime.bench;

import dev.prime.mcap.McapChannel;
import dev.prime.mcap.McapWriter;
import dev.prime.mcap.McapWriterOptions;
import dev.prime.mcap.ValueType;
import java.io.IOException;
import java.nio.file.Path;
import java.util.List;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.AuxCounters;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;

/**
 * Cost of recording one value with prime-mcap, for a small record (a pose, ~40 bytes of JSON)
 * and a larger one (a status with a list and a map, ~200 bytes). Files go to {@code /dev/null},
 * so the figures are the CPU cost, not the disk's.
 *
 * <p>{@code encode}: the value to JSON (what a queued write does in the caller's thread before
 * the hand-off). {@code synchronousWrite}: the whole cost per message in one thread (JSON, the
 * chunk, the message index, the CRC32s, the write): the most messages per second one writer
 * thread can take. {@code queuedWrite}: the caller's cost with the background writer; the
 * {@code accepted} and {@code dropped} counters show how much of a flat-out caller the writer
 * thread kept up with.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 3, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(1)
public class McapWriterBenchmark {

  /**
   * A robot pose.
   *
   * @param x metres
   * @param y metres
   * @param theta radians
   */
  public record Pose(double x, double y, double theta) {}

  /**
   * A status report.
   *
   * @param mode a mode name
   * @param pose where the robot is
   * @param faults fault codes
   * @param gains controller gains by name
   */
  public record Status(String mode, Pose pose, List<Integer> faults, java.util.Map<String, Double> gains) {}

  /** Values, their types and writers. */
  @State(Scope.Thread)
  public static class Recording {
    /** The pose's value type. */
    public final ValueType<Pose> poseType = ValueType.of(Pose.class);
    /** A pose. */
    public final Pose pose = new Pose(1.2345, -0.5, 0.785);
    /** The status' value type. */
    public final ValueType<Status> statusType = ValueType.of(Status.class);
    /** A status. */
    public final Status status = new Status("DRIVING", pose, List.of(3, 17, 42),
        java.util.Map.of("kp", 1.5, "ki", 0.01, "kd", 0.2));
    /** A synchronous writer to /dev/null. */
    public McapWriter synchronous;
    /** Its pose channel. */
    public McapChannel<Pose> synchronousPoses;
    /** Its status channel. */
    public McapChannel<Status> synchronousStatus;
    /** A queued writer to /dev/null. */
    public McapWriter queued;
    /** Its pose channel. */
    public McapChannel<Pose> queuedPoses;
    /** A running time stamp. */
    public long time;

    /**
     * Opens the writers.
     *
     * @throws IOException if /dev/null cannot be opened
     */
    @Setup(Level.Trial)
    public void open() throws IOException {
      synchronous = McapWriter.open(Path.of("/dev/null"), McapWriterOptions.defaults().synchronous());
      synchronousPoses = synchronous.channel("poses", Pose.class);
      synchronousStatus = synchronous.channel("status", Status.class);
      queued = McapWriter.open(Path.of("/dev/null"), McapWriterOptions.defaults());
      queuedPoses = queued.channel("poses", Pose.class);
    }

    /**
     * Closes the writers.
     *
     * @throws IOException from closing
     */
    @TearDown(Level.Trial)
    public void close() throws IOException {
      synchronous.close();
      queued.close();
    }
  }

  /** What became of the queued writes. */
  @State(Scope.Thread)
  @AuxCounters(AuxCounters.Type.EVENTS)
  public static class Outcome {
    /** Writes the queue took. */
    public long accepted;
    /** Writes dropped because the queue was full. */
    public long dropped;

    /** Zeroes the counters. */
    @Setup(Level.Iteration)
    public void reset() {
      accepted = 0;
      dropped = 0;
    }
  }

  /**
   * @param r the recording
   * @return the pose's JSON
   */
  @Benchmark
  public byte[] encodePose(Recording r) {
    return r.poseType.toJson(r.pose);
  }

  /**
   * @param r the recording
   * @return the status' JSON
   */
  @Benchmark
  public byte[] encodeStatus(Recording r) {
    return r.statusType.toJson(r.status);
  }

  /**
   * @param r the recording
   * @return whether the write was accepted
   */
  @Benchmark
  public boolean synchronousWritePose(Recording r) {
    long t = r.time++;
    return r.synchronousPoses.write(t, t, t, r.pose);
  }

  /**
   * @param r the recording
   * @return whether the write was accepted
   */
  @Benchmark
  public boolean synchronousWriteStatus(Recording r) {
    long t = r.time++;
    return r.synchronousStatus.write(t, t, t, r.status);
  }

  /**
   * @param r the recording
   * @param outcome counts accepted and dropped writes
   * @return whether the write was accepted
   */
  @Benchmark
  public boolean queuedWritePose(Recording r, Outcome outcome) {
    long t = r.time++;
    boolean accepted = r.queuedPoses.write(t, t, t, r.pose);
    if (accepted) {
      outcome.accepted++;
    } else {
      outcome.dropped++;
    }
    return accepted;
  }
}
