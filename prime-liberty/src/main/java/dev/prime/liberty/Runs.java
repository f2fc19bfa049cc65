package dev.prime.liberty;

import dev.prime.Block;
import java.util.List;

/**
 * Runs of one to sixteen steps of a flattened chain, written out: {@code Run3.process(x)} is
 * {@code b3.process(b2.process(b1.process(x)))} with the failing step's chain named on failure.
 *
 * <p>Design note. Each position of each run has its own call site, and no run calls a run, so
 * the JIT inlines a whole run (and, through {@link RunSequences} and {@link RunLoop}, a whole chain) instead of
 * stopping after one level of a recursive composition; a call site sees only the blocks that
 * stand at its position in chains of its run's length, so a program's profile is split sixteen
 * ways per length instead of meeting in one shared site. The failing position is tracked in a
 * local ({@code at}), which costs nothing on the normal path; only a failure reads it.
 */
final class Runs {
  /** The longest run; longer chains are sequences of runs. */
  static final int MAX_LENGTH = 16;

  private Runs() {}

  /**
   * The run of the given steps.
   *
   * @param steps one to {@link #MAX_LENGTH} steps, in order
   * @return a block that runs them
   */
  static Block<Object, Object> of(List<Step> steps) {
    Step[] s = steps.toArray(new Step[0]);
    return switch (s.length) {
      case 1 -> new Run1(s);
      case 2 -> new Run2(s);
      case 3 -> new Run3(s);
      case 4 -> new Run4(s);
      case 5 -> new Run5(s);
      case 6 -> new Run6(s);
      case 7 -> new Run7(s);
      case 8 -> new Run8(s);
      case 9 -> new Run9(s);
      case 10 -> new Run10(s);
      case 11 -> new Run11(s);
      case 12 -> new Run12(s);
      case 13 -> new Run13(s);
      case 14 -> new Run14(s);
      case 15 -> new Run15(s);
      case 16 -> new Run16(s);
      default -> throw new IllegalArgumentException(
          "a run has 1 to " + MAX_LENGTH + " steps, not " + s.length);
    };
  }

  /** One step. */
  static final class Run1 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;

    Run1(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
    }

    @Override
    public Object process(Object input) {
      try {
        return b1.process(input);
      } catch (Throwable e) {
        throw steps[0].failed(e);
      }
    }
  }

  /** Two steps. */
  static final class Run2 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;

    Run2(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        return b2.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Three steps. */
  static final class Run3 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;

    Run3(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        return b3.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Four steps. */
  static final class Run4 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;

    Run4(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        return b4.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Five steps. */
  static final class Run5 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;

    Run5(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        return b5.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Six steps. */
  static final class Run6 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;

    Run6(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        return b6.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Seven steps. */
  static final class Run7 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;

    Run7(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        return b7.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Eight steps. */
  static final class Run8 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;

    Run8(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        return b8.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Nine steps. */
  static final class Run9 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;

    Run9(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        return b9.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Ten steps. */
  static final class Run10 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;
    private final Block<Object, Object> b10;

    Run10(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
      b10 = steps[9].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        x = b9.process(x);
        at = 9;
        return b10.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Eleven steps. */
  static final class Run11 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;
    private final Block<Object, Object> b10;
    private final Block<Object, Object> b11;

    Run11(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
      b10 = steps[9].block();
      b11 = steps[10].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        x = b9.process(x);
        at = 9;
        x = b10.process(x);
        at = 10;
        return b11.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Twelve steps. */
  static final class Run12 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;
    private final Block<Object, Object> b10;
    private final Block<Object, Object> b11;
    private final Block<Object, Object> b12;

    Run12(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
      b10 = steps[9].block();
      b11 = steps[10].block();
      b12 = steps[11].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        x = b9.process(x);
        at = 9;
        x = b10.process(x);
        at = 10;
        x = b11.process(x);
        at = 11;
        return b12.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Thirteen steps. */
  static final class Run13 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;
    private final Block<Object, Object> b10;
    private final Block<Object, Object> b11;
    private final Block<Object, Object> b12;
    private final Block<Object, Object> b13;

    Run13(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
      b10 = steps[9].block();
      b11 = steps[10].block();
      b12 = steps[11].block();
      b13 = steps[12].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        x = b9.process(x);
        at = 9;
        x = b10.process(x);
        at = 10;
        x = b11.process(x);
        at = 11;
        x = b12.process(x);
        at = 12;
        return b13.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Fourteen steps. */
  static final class Run14 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;
    private final Block<Object, Object> b10;
    private final Block<Object, Object> b11;
    private final Block<Object, Object> b12;
    private final Block<Object, Object> b13;
    private final Block<Object, Object> b14;

    Run14(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
      b10 = steps[9].block();
      b11 = steps[10].block();
      b12 = steps[11].block();
      b13 = steps[12].block();
      b14 = steps[13].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        x = b9.process(x);
        at = 9;
        x = b10.process(x);
        at = 10;
        x = b11.process(x);
        at = 11;
        x = b12.process(x);
        at = 12;
        x = b13.process(x);
        at = 13;
        return b14.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Fifteen steps. */
  static final class Run15 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;
    private final Block<Object, Object> b10;
    private final Block<Object, Object> b11;
    private final Block<Object, Object> b12;
    private final Block<Object, Object> b13;
    private final Block<Object, Object> b14;
    private final Block<Object, Object> b15;

    Run15(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
      b10 = steps[9].block();
      b11 = steps[10].block();
      b12 = steps[11].block();
      b13 = steps[12].block();
      b14 = steps[13].block();
      b15 = steps[14].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        x = b9.process(x);
        at = 9;
        x = b10.process(x);
        at = 10;
        x = b11.process(x);
        at = 11;
        x = b12.process(x);
        at = 12;
        x = b13.process(x);
        at = 13;
        x = b14.process(x);
        at = 14;
        return b15.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }

  /** Sixteen steps. */
  static final class Run16 implements Block<Object, Object> {
    private final Step[] steps;
    private final Block<Object, Object> b1;
    private final Block<Object, Object> b2;
    private final Block<Object, Object> b3;
    private final Block<Object, Object> b4;
    private final Block<Object, Object> b5;
    private final Block<Object, Object> b6;
    private final Block<Object, Object> b7;
    private final Block<Object, Object> b8;
    private final Block<Object, Object> b9;
    private final Block<Object, Object> b10;
    private final Block<Object, Object> b11;
    private final Block<Object, Object> b12;
    private final Block<Object, Object> b13;
    private final Block<Object, Object> b14;
    private final Block<Object, Object> b15;
    private final Block<Object, Object> b16;

    Run16(Step[] steps) {
      this.steps = steps;
      b1 = steps[0].block();
      b2 = steps[1].block();
      b3 = steps[2].block();
      b4 = steps[3].block();
      b5 = steps[4].block();
      b6 = steps[5].block();
      b7 = steps[6].block();
      b8 = steps[7].block();
      b9 = steps[8].block();
      b10 = steps[9].block();
      b11 = steps[10].block();
      b12 = steps[11].block();
      b13 = steps[12].block();
      b14 = steps[13].block();
      b15 = steps[14].block();
      b16 = steps[15].block();
    }

    @Override
    public Object process(Object input) {
      Object x = input;
      int at = 0;
      try {
        x = b1.process(x);
        at = 1;
        x = b2.process(x);
        at = 2;
        x = b3.process(x);
        at = 3;
        x = b4.process(x);
        at = 4;
        x = b5.process(x);
        at = 5;
        x = b6.process(x);
        at = 6;
        x = b7.process(x);
        at = 7;
        x = b8.process(x);
        at = 8;
        x = b9.process(x);
        at = 9;
        x = b10.process(x);
        at = 10;
        x = b11.process(x);
        at = 11;
        x = b12.process(x);
        at = 12;
        x = b13.process(x);
        at = 13;
        x = b14.process(x);
        at = 14;
        x = b15.process(x);
        at = 15;
        return b16.process(x);
      } catch (Throwable e) {
        throw steps[at].failed(e);
      }
    }
  }
}
