package dev.prime.liberty;

import dev.prime.Block;
import java.util.List;

/**
 * Two to eight {@link Runs runs} of a flattened chain, written out:
 * {@code Seq3.process(x)} is {@code r3.process(r2.process(r1.process(x)))}.
 *
 * <p>Design note. The middle tier of a flat composition (see {@link FlatComposition}): a chain of
 * up to {@code MAX_RUNS × Runs.MAX_LENGTH} blocks is one sequence of runs, every run inlined at a
 * call site of its own, with no loop between them. A sequence only ever calls runs and a run only
 * ever calls blocks, so no class calls itself and the JIT's limit on recursive inlining never
 * applies. The runs name failing chains; a sequence adds nothing on the failure path.
 */
final class RunSequences {
  /** The most runs in one sequence; longer chains are a {@link RunLoop} of sequences. */
  static final int MAX_RUNS = 8;

  private RunSequences() {}

  /**
   * The sequence of the given runs.
   *
   * @param runs two to {@link #MAX_RUNS} runs, in order
   * @return a block that runs them
   */
  static Block<Object, Object> of(List<Block<Object, Object>> runs) {
    return switch (runs.size()) {
      case 2 -> new Seq2(runs);
      case 3 -> new Seq3(runs);
      case 4 -> new Seq4(runs);
      case 5 -> new Seq5(runs);
      case 6 -> new Seq6(runs);
      case 7 -> new Seq7(runs);
      case 8 -> new Seq8(runs);
      default -> throw new IllegalArgumentException(
          "a sequence has 2 to " + MAX_RUNS + " runs, not " + runs.size());
    };
  }

  /** Two runs. */
  static final class Seq2 implements Block<Object, Object> {
    private final Block<Object, Object> r1;
    private final Block<Object, Object> r2;

    Seq2(List<Block<Object, Object>> runs) {
      r1 = runs.get(0);
      r2 = runs.get(1);
    }

    @Override
    public Object process(Object input) {
      Object x = r1.process(input);
      return r2.process(x);
    }
  }

  /** Three runs. */
  static final class Seq3 implements Block<Object, Object> {
    private final Block<Object, Object> r1;
    private final Block<Object, Object> r2;
    private final Block<Object, Object> r3;

    Seq3(List<Block<Object, Object>> runs) {
      r1 = runs.get(0);
      r2 = runs.get(1);
      r3 = runs.get(2);
    }

    @Override
    public Object process(Object input) {
      Object x = r1.process(input);
      x = r2.process(x);
      return r3.process(x);
    }
  }

  /** Four runs. */
  static final class Seq4 implements Block<Object, Object> {
    private final Block<Object, Object> r1;
    private final Block<Object, Object> r2;
    private final Block<Object, Object> r3;
    private final Block<Object, Object> r4;

    Seq4(List<Block<Object, Object>> runs) {
      r1 = runs.get(0);
      r2 = runs.get(1);
      r3 = runs.get(2);
      r4 = runs.get(3);
    }

    @Override
    public Object process(Object input) {
      Object x = r1.process(input);
      x = r2.process(x);
      x = r3.process(x);
      return r4.process(x);
    }
  }

  /** Five runs. */
  static final class Seq5 implements Block<Object, Object> {
    private final Block<Object, Object> r1;
    private final Block<Object, Object> r2;
    private final Block<Object, Object> r3;
    private final Block<Object, Object> r4;
    private final Block<Object, Object> r5;

    Seq5(List<Block<Object, Object>> runs) {
      r1 = runs.get(0);
      r2 = runs.get(1);
      r3 = runs.get(2);
      r4 = runs.get(3);
      r5 = runs.get(4);
    }

    @Override
    public Object process(Object input) {
      Object x = r1.process(input);
      x = r2.process(x);
      x = r3.process(x);
      x = r4.process(x);
      return r5.process(x);
    }
  }

  /** Six runs. */
  static final class Seq6 implements Block<Object, Object> {
    private final Block<Object, Object> r1;
    private final Block<Object, Object> r2;
    private final Block<Object, Object> r3;
    private final Block<Object, Object> r4;
    private final Block<Object, Object> r5;
    private final Block<Object, Object> r6;

    Seq6(List<Block<Object, Object>> runs) {
      r1 = runs.get(0);
      r2 = runs.get(1);
      r3 = runs.get(2);
      r4 = runs.get(3);
      r5 = runs.get(4);
      r6 = runs.get(5);
    }

    @Override
    public Object process(Object input) {
      Object x = r1.process(input);
      x = r2.process(x);
      x = r3.process(x);
      x = r4.process(x);
      x = r5.process(x);
      return r6.process(x);
    }
  }

  /** Seven runs. */
  static final class Seq7 implements Block<Object, Object> {
    private final Block<Object, Object> r1;
    private final Block<Object, Object> r2;
    private final Block<Object, Object> r3;
    private final Block<Object, Object> r4;
    private final Block<Object, Object> r5;
    private final Block<Object, Object> r6;
    private final Block<Object, Object> r7;

    Seq7(List<Block<Object, Object>> runs) {
      r1 = runs.get(0);
      r2 = runs.get(1);
      r3 = runs.get(2);
      r4 = runs.get(3);
      r5 = runs.get(4);
      r6 = runs.get(5);
      r7 = runs.get(6);
    }

    @Override
    public Object process(Object input) {
      Object x = r1.process(input);
      x = r2.process(x);
      x = r3.process(x);
      x = r4.process(x);
      x = r5.process(x);
      x = r6.process(x);
      return r7.process(x);
    }
  }

  /** Eight runs. */
  static final class Seq8 implements Block<Object, Object> {
    private final Block<Object, Object> r1;
    private final Block<Object, Object> r2;
    private final Block<Object, Object> r3;
    private final Block<Object, Object> r4;
    private final Block<Object, Object> r5;
    private final Block<Object, Object> r6;
    private final Block<Object, Object> r7;
    private final Block<Object, Object> r8;

    Seq8(List<Block<Object, Object>> runs) {
      r1 = runs.get(0);
      r2 = runs.get(1);
      r3 = runs.get(2);
      r4 = runs.get(3);
      r5 = runs.get(4);
      r6 = runs.get(5);
      r7 = runs.get(6);
      r8 = runs.get(7);
    }

    @Override
    public Object process(Object input) {
      Object x = r1.process(input);
      x = r2.process(x);
      x = r3.process(x);
      x = r4.process(x);
      x = r5.process(x);
      x = r6.process(x);
      x = r7.process(x);
      return r8.process(x);
    }
  }
}
