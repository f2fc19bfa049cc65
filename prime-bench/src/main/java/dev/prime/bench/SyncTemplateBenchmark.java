package dev.prime.bench;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.PrimeCore;
import dev.prime.Tuple2;
import dev.prime.bench.PacketBlocks.Add;
import dev.prime.radiant.RadiantCore;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.function.Predicate;
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
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;

/**
 * Synchronous chains made of templates, Radiant against the same blocks called by hand (FOR):
 * {@code length} ({@link Shape}'s) is the number of adders each transmission runs, as in
 * {@link SyncChainBenchmark}; in the polluted scenario the other chains of {@link Shape} run
 * too.
 *
 * <ul>
 *   <li>{@code if}: {@code length} if/else steps, each choosing one of two adders by the parity
 *       of the value (which keeps changing, so both branches stay hot);
 *   <li>{@code union}: {@code length / 2} unions of two adders, each followed by a block that
 *       takes the tuple's second part;
 *   <li>{@code forEach}: a for-each over a list of four packets whose body is a chain of
 *       {@code length} adders (four times {@code length} adders per transmission, and one result
 *       list, in both methods).
 * </ul>
 *
 * FOR writes each template out as Java code: a conditional, a tuple built and read, a loop that
 * fills a list. See README.md for the command.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class SyncTemplateBenchmark {

  /** The parity test of the if/else steps; public, so Radiant calls it by its own class. */
  public static final class IsEven implements Predicate<Packet> {
    @Override
    public boolean test(Packet packet) {
      return (packet.value & 1) == 0;
    }
  }

  /** Takes the second part of a union's tuple. */
  public static final class Second implements Block<Tuple2<Packet, Packet>, Packet> {
    @Override
    public Packet process(Tuple2<Packet, Packet> tuple) {
      return tuple.second();
    }
  }

  private static final int IF = 0;
  private static final int UNION = 1;
  private static final int FOR_EACH = 2;

  /**
   * The shape and the blocks, built once per trial; the length, payload and scenario are
   * {@link Shape}'s, as in {@link SyncChainBenchmark}.
   */
  @State(Scope.Thread)
  public static class Template {
    /** {@code if}, {@code union} or {@code forEach}. */
    @Param({"if", "union", "forEach"})
    public String shape;

    /** The shape as a number, so both methods choose their code the same, cheap way. */
    public int kind;

    /** The packet sent through the if and union chains. */
    public Packet packet;

    /** The packets sent through the for-each chain. */
    public List<Packet> packets;

    /** FOR: the condition. */
    public IsEven even;

    /** FOR: the adders of the if branches, the first parts of the unions, the for-each body. */
    public Add[] first;

    /** FOR: the adders of the else branches, the second parts of the unions. */
    public Add[] second;

    /** FOR: what follows each union. */
    public Second pick;

    /** Radiant: the chain's block (its input is a packet, or a list of packets for forEach). */
    public Block<Object, Object> radiant;

    private RadiantCore core;

    /**
     * Builds the blocks and the chain.
     *
     * @param parameters the length (adders per transmission) and the payload
     */
    @Setup(Level.Trial)
    @SuppressWarnings("unchecked")
    public void build(Shape parameters) {
      int length = parameters.length;
      packet = Packet.ofSize(parameters.payload);
      packets =
          List.of(
              Packet.ofSize(parameters.payload),
              Packet.ofSize(parameters.payload),
              Packet.ofSize(parameters.payload),
              Packet.ofSize(parameters.payload));
      even = new IsEven();
      pick = new Second();
      int steps = shape.equals("union") ? Math.max(1, length / 2) : length;
      first = new Add[steps];
      second = new Add[steps];
      for (int i = 0; i < steps; i++) {
        first[i] = new Add(2L * i + 1);
        second[i] = new Add(2L * i + 3); // both odd: the parity flips at every step
      }
      switch (shape) {
        case "if" -> kind = IF;
        case "union" -> kind = UNION;
        case "forEach" -> kind = FOR_EACH;
        default -> throw new IllegalArgumentException(
            "shape must be if, union or forEach, not " + shape);
      }
      core = new RadiantCore();
      radiant = (Block<Object, Object>) (Block<?, ?>) chain(core);
    }

    private Block<?, ?> chain(PrimeCore core) {
      switch (kind) {
        case IF -> {
          Chain<Packet, Packet> chain = ifStep(core, 0);
          for (int i = 1; i < first.length; i++) {
            chain = chain.then(ifStep(core, i));
          }
          return chain.toBlock();
        }
        case UNION -> {
          Chain<Packet, Packet> chain = unionStep(core, 0);
          for (int i = 1; i < first.length; i++) {
            chain = chain.then(unionStep(core, i));
          }
          return chain.toBlock();
        }
        default -> {
          Chain<Packet, Packet> body = core.chain(first[0]);
          for (int i = 1; i < first.length; i++) {
            body = body.then(first[i]);
          }
          return core.forEach(body).toBlock();
        }
      }
    }

    private Chain<Packet, Packet> ifStep(PrimeCore core, int i) {
      return core.ifThenElse(even, core.chain(first[i]), core.chain(second[i]));
    }

    private Chain<Packet, Packet> unionStep(PrimeCore core, int i) {
      return core.union(core.chain(first[i]), core.chain(second[i])).then(pick);
    }

    /** Closes the core. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /**
   * FOR: the templates written out by hand.
   *
   * @param t the blocks
   * @param clock CPU time per operation, for {@code -prof dev.prime.bench.WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long forHandWritten(Template t, WorkerCpuTime.Clock clock) {
    switch (t.kind) {
      case IF -> {
        Packet packet = t.packet;
        for (int i = 0; i < t.first.length; i++) {
          packet = t.even.test(packet) ? t.first[i].process(packet) : t.second[i].process(packet);
        }
        return packet.value;
      }
      case UNION -> {
        Packet packet = t.packet;
        for (int i = 0; i < t.first.length; i++) {
          Packet a = t.first[i].process(packet);
          Packet b = t.second[i].process(packet);
          packet = t.pick.process(new Tuple2<>(a, b));
        }
        return packet.value;
      }
      default -> {
        List<Packet> in = t.packets;
        List<Packet> out = new ArrayList<>(in.size());
        for (Packet element : in) {
          Packet packet = element;
          for (Add adder : t.first) {
            packet = adder.process(packet);
          }
          out.add(packet);
        }
        return out.get(out.size() - 1).value;
      }
    }
  }

  /**
   * Radiant: the chain of templates as one generated class.
   *
   * @param t the chain
   * @param clock CPU time per operation, for {@code -prof dev.prime.bench.WorkerCpuTime}
   * @return the result
   */
  @Benchmark
  public long radiant(Template t, WorkerCpuTime.Clock clock) {
    if (t.kind == FOR_EACH) {
      @SuppressWarnings("unchecked")
      List<Packet> out = (List<Packet>) t.radiant.process(t.packets);
      return out.get(out.size() - 1).value;
    }
    return ((Packet) t.radiant.process(t.packet)).value;
  }
}
