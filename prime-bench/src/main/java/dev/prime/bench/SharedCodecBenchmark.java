package dev.prime.bench;

import dev.prime.optimus.HeldCodecSession;
import dev.prime.optimus.KryoCodec;
import dev.prime.optimus.OptimusCodec;
import java.util.concurrent.TimeUnit;
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
import org.openjdk.jmh.annotations.Threads;
import org.openjdk.jmh.annotations.Warmup;

/**
 * One {@link KryoCodec} used by two threads at once, as an Optimus core's codec is (its publisher,
 * services and readers encode and decode on their own threads): what sharing the codec's pool of
 * Kryo sessions costs per round trip (encode, then decode) of a 100 B value.
 *
 * <p>{@code baseline}: each thread has a codec of its own, so nothing is shared between the
 * threads. {@code shared}: both threads use one codec, each taking a session from its pool and
 * giving it back on every encode and every decode. {@code held}: both threads use one codec, each
 * keeping one session of it for all its values, as an Optimus service and reader do.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
@Threads(2)
public class SharedCodecBenchmark {

  /** A codec and a 100 B value to round-trip through it. */
  public abstract static class Codec {
    /** The codec. */
    public OptimusCodec codec;

    /** The value: a 100-byte array. */
    public byte[] value;

    /** Builds the codec and the value. */
    @Setup(Level.Trial)
    public void build() {
      codec = KryoCodec.standard();
      value = new byte[100];
      for (int i = 0; i < value.length; i++) {
        value[i] = (byte) i;
      }
    }
  }

  /** A codec of each thread's own. */
  @State(Scope.Thread)
  public static class OwnCodec extends Codec {}

  /** One codec both threads use. */
  @State(Scope.Benchmark)
  public static class OneCodec extends Codec {}

  /** A session of the shared codec, kept by one thread for all its values. */
  @State(Scope.Thread)
  public static class Held {
    /** The thread's session. */
    public HeldCodecSession session;

    /**
     * Takes the thread's session of the shared codec.
     *
     * @param codec the codec both threads use
     */
    @Setup(Level.Trial)
    public void hold(OneCodec codec) {
      session = new HeldCodecSession((KryoCodec) codec.codec);
    }

    /** Gives the session back. */
    @TearDown(Level.Trial)
    public void giveBack() {
      session.close();
    }
  }

  /**
   * Encode and decode with the thread's own codec.
   *
   * @param codec the state
   * @return the value read back
   */
  @Benchmark
  public Object baseline(OwnCodec codec) {
    return codec.codec.decode(codec.codec.encode(codec.value));
  }

  /**
   * Encode and decode with the codec both threads share.
   *
   * @param codec the state
   * @return the value read back
   */
  @Benchmark
  public Object shared(OneCodec codec) {
    return codec.codec.decode(codec.codec.encode(codec.value));
  }

  /**
   * Encode and decode with a session of the shared codec that the thread keeps.
   *
   * @param codec the codec both threads use (for the value)
   * @param held the thread's session
   * @return the value read back
   */
  @Benchmark
  public Object held(OneCodec codec, Held held) {
    byte[] bytes = held.session.encode(codec.value, 0);
    return held.session.decode(bytes, 0, bytes.length);
  }
}
