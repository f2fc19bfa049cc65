package dev.prime.bench;

import dev.prime.Block;
import dev.prime.liberty.LibertyCore;
import dev.prime.radiant.RadiantCore;
import java.util.ArrayList;
import java.util.List;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;

/**
 * The benchmark's parameters and, in the polluted scenario, the other chains of the program.
 *
 * <p>Polluted: ten chains of other shapes and block classes are built in a Liberty and a Radiant
 * core and driven before warm-up (so the JIT's profiles of the shared code see them) and again
 * before every iteration (so they stay in the program during measurement), whatever is measured.
 */
@State(Scope.Thread)
public class Shape {
  /**
   * Blocks in the measured chain; the paper's experiment has 4 (the suite's runner passes it);
   * {@code SyncChainBenchmark}'s sweep passes {@code -p length=1,4,16,32,64} (see README.md).
   */
  @Param({"4"})
  public int length;

  /** Bytes of data each packet carries: the paper's small, medium and big data. */
  @Param({"100", "1024", "10240"})
  public int payload;

  /** {@code monomorphic}: only the measured chain exists; {@code polluted}: see the class docs. */
  @Param({"monomorphic", "polluted"})
  public String scenario;

  /** Keeps the driving loops' results alive. */
  public long sink;

  private final List<Block<Packet, Packet>> polluters = new ArrayList<>();
  private LibertyCore liberty;
  private RadiantCore radiant;

  /** Builds and drives the polluting chains, if the scenario asks for them. */
  @Setup(Level.Trial)
  public void buildPolluters() {
    switch (scenario) {
      case "monomorphic" -> {}
      case "polluted" -> {
        liberty = new LibertyCore();
        radiant = new RadiantCore();
        polluters.addAll(ChainShapes.polluters(liberty));
        polluters.addAll(ChainShapes.polluters(radiant));
        drivePolluters();
      }
      default -> throw new IllegalArgumentException(
          "scenario must be monomorphic or polluted, not " + scenario);
    }
  }

  /** Drives the polluting chains again between iterations. */
  @Setup(Level.Iteration)
  public void drivePolluters() {
    if (!polluters.isEmpty()) {
      sink += ChainShapes.drive(polluters);
    }
  }

  /** Closes the polluting cores. */
  @TearDown(Level.Trial)
  public void close() {
    if (liberty != null) {
      liberty.close();
      radiant.close();
    }
  }
}
