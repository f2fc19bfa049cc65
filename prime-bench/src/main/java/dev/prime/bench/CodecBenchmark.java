package dev.prime.bench;

import dev.prime.optimus.KryoCodec;
import dev.prime.optimus.OptimusCodec;
import java.util.Arrays;
import java.util.Objects;
import java.util.Random;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.Warmup;

/**
 * Cost of Optimus' default codec ({@link KryoCodec}) per value: encode, decode and both, for a
 * registered record whose encoding is exactly {@code size} bytes (100 B, 1 KB, 10 KB), with its
 * payload as a {@code byte[]} or as ASCII text.
 *
 * <p>{@code baseline} allocates a {@code byte[]} of the encoded size and copies the encoding into
 * it: the least any codec must do to hand Redis a fresh array of that size. {@code encode} also
 * ends in such a copy (the codec's pooled buffer is reused, the returned bytes are not).
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class CodecBenchmark {

  /**
   * A typical message between services: a few numbers and a payload.
   *
   * @param id message id
   * @param timestampNanos when it was made
   * @param x a measurement
   * @param y another measurement
   * @param sequence position in its stream
   * @param payload raw bytes, or null when {@code text} carries the payload
   * @param text text, or null when {@code payload} carries it
   */
  public record Reading(
      long id, long timestampNanos, double x, double y, int sequence, byte[] payload, String text) {}

  /** The codec, the value and its encoding. */
  @State(Scope.Thread)
  public static class Sample {
    /** Encoded size of the value, in bytes. */
    @Param({"100", "1000", "10000"})
    public int size;

    /** {@code bytes}: payload is a byte[]; {@code text}: payload is an ASCII String. */
    @Param({"bytes", "text"})
    public String payload;

    /** The codec under test, with {@link Reading} registered. */
    public OptimusCodec codec;

    /** The value to encode. */
    public Reading value;

    /** Its encoding, to decode. */
    public byte[] encoded;

    /** Sets up a value whose encoding is exactly {@link #size} bytes. */
    @Setup(Level.Trial)
    public void build() {
      codec = KryoCodec.builder().register(Reading.class).build();
      int length = size;
      while (length > 0 && codec.encode(reading(length)).length > size) {
        length--;
      }
      value = reading(length);
      encoded = codec.encode(value);
      if (encoded.length != size) {
        throw new IllegalStateException(
            "could not size the value to " + size + " bytes (got " + encoded.length + ")");
      }
      Reading back = (Reading) codec.decode(encoded);
      if (back.timestampNanos() != value.timestampNanos()
          || !Arrays.equals(back.payload(), value.payload())
          || !Objects.equals(back.text(), value.text())) {
        throw new IllegalStateException("the value does not round-trip");
      }
    }

    private Reading reading(int payloadLength) {
      Random random = new Random(42);
      if ("bytes".equals(payload)) {
        byte[] bytes = new byte[payloadLength];
        random.nextBytes(bytes);
        return new Reading(123_456_789L, System.nanoTime(), 1.25, -3.5, 77, bytes, null);
      }
      StringBuilder text = new StringBuilder(payloadLength);
      for (int i = 0; i < payloadLength; i++) {
        text.append((char) ('a' + random.nextInt(26)));
      }
      return new Reading(123_456_789L, System.nanoTime(), 1.25, -3.5, 77, null, text.toString());
    }
  }

  /**
   * A fresh byte[] of the encoded size, filled by a copy: the floor for any codec.
   *
   * @param sample the state
   * @return the copy
   */
  @Benchmark
  public byte[] baseline(Sample sample) {
    byte[] copy = new byte[sample.encoded.length];
    System.arraycopy(sample.encoded, 0, copy, 0, copy.length);
    return copy;
  }

  /**
   * Value to bytes.
   *
   * @param sample the state
   * @return the encoding
   */
  @Benchmark
  public byte[] encode(Sample sample) {
    return sample.codec.encode(sample.value);
  }

  /**
   * Bytes to value.
   *
   * @param sample the state
   * @return the value
   */
  @Benchmark
  public Object decode(Sample sample) {
    return sample.codec.decode(sample.encoded);
  }

  /**
   * Value to bytes and back, as one hop through Redis costs in codec work.
   *
   * @param sample the state
   * @return the value
   */
  @Benchmark
  public Object roundTrip(Sample sample) {
    return sample.codec.decode(sample.codec.encode(sample.value));
  }
}
