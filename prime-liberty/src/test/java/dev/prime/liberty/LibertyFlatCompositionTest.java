package dev.prime.liberty;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * The flat composition of linked chains, at every length around its run size: each block runs
 * once and in order, and a failure at any position names that position's chain.
 */
class LibertyFlatCompositionTest {
  private static final int LONGEST = 2 * Runs.MAX_LENGTH + 3;

  @Test
  void everyLengthRunsEveryBlockInOrder() {
    try (LibertyCore core = new LibertyCore()) {
      core.start();
      for (int length = 1; length <= LONGEST; length++) {
        Chain<List<Integer>, List<Integer>> chain = core.chain(appending(0));
        for (int i = 1; i < length; i++) {
          chain = chain.then(appending(i));
        }
        List<Integer> expected = new ArrayList<>();
        for (int i = 0; i < length; i++) {
          expected.add(i);
        }
        assertEquals(expected, chain.toBlock().process(List.of()), "length " + length);
      }
    }
  }

  @Test
  void failureAtEveryPositionNamesThatPositionsChain() {
    IllegalArgumentException boom = new IllegalArgumentException("boom");
    try (LibertyCore core = new LibertyCore()) {
      core.start();
      for (int length = 1; length <= LONGEST; length++) {
        for (int failing = 0; failing < length; failing++) {
          Chain<Integer, Integer> chain = null;
          for (int i = 0; i < length; i++) {
            Block<Integer, Integer> block =
                i == failing
                    ? x -> {
                      throw boom;
                    }
                    : x -> x + 1;
            Chain<Integer, Integer> step = core.chain("n" + length + "-f" + failing + "-" + i, block);
            chain = chain == null ? step : chain.then(step);
          }
          Block<Integer, Integer> block = chain.toBlock();
          ChainFailedException e =
              assertThrows(ChainFailedException.class, () -> block.process(0));
          assertEquals("n" + length + "-f" + failing + "-" + failing, e.chainName());
          assertSame(boom, e.getCause());
        }
      }
    }
  }

  @Test
  void foreignFailureAtAnyPositionPassesUnchanged() {
    IllegalStateException boom = new IllegalStateException("foreign boom");
    try (LibertyCore core = new LibertyCore();
        LibertyCore other = new LibertyCore()) {
      core.start();
      other.start();
      for (int failing = 0; failing < LONGEST; failing++) {
        Chain<Integer, Integer> chain = null;
        for (int i = 0; i < LONGEST; i++) {
          Chain<Integer, Integer> step =
              i == failing
                  ? other.chain(
                      "foreign-" + failing,
                      x -> {
                        throw boom;
                      })
                  : core.chain((Integer x) -> x + 1);
          chain = chain == null ? step : core.link(chain, step);
        }
        Block<Integer, Integer> block = chain.toBlock();
        ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process(0));
        assertEquals("foreign-" + failing, e.chainName(), "the foreign chain named itself");
        assertSame(boom, e.getCause());
      }
    }
  }

  @Test
  void eachTierIsUsedFromItsLength() {
    int run = Runs.MAX_LENGTH;
    int sequence = Runs.MAX_LENGTH * RunSequences.MAX_RUNS;
    assertEquals(Runs.Run1.class, shapeOf(1));
    assertEquals(Runs.class, shapeOf(run).getEnclosingClass());
    assertEquals(RunSequences.Seq2.class, shapeOf(run + 1));
    assertEquals(RunSequences.class, shapeOf(sequence).getEnclosingClass());
    assertEquals(RunLoop.class, shapeOf(sequence + 1));
  }

  @Test
  void longChainsRunEveryBlockInOrderAndNameTheFailingOne() {
    int sequence = Runs.MAX_LENGTH * RunSequences.MAX_RUNS;
    IllegalArgumentException boom = new IllegalArgumentException("boom");
    try (LibertyCore core = new LibertyCore()) {
      core.start();
      for (int length : new int[] {sequence, sequence + 1, 2 * sequence + Runs.MAX_LENGTH + 3}) {
        assertEquals((long) length, adders(core, length, -1, boom).toBlock().process(0L));
        for (int failing : new int[] {0, length / 2, length - 1}) {
          Block<Long, Long> block = adders(core, length, failing, boom).toBlock();
          ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process(0L));
          assertEquals(name(length, failing, failing), e.chainName());
          assertSame(boom, e.getCause());
        }
      }
    }
  }

  /**
   * "A linked call costs a few method invocations": every block of a linked chain, of any length,
   * is called at most three frames (run, sequence, loop) below the caller of the chain's block,
   * never a frame per link.
   */
  @Test
  void everyBlockRunsAtMostThreeFramesBelowTheCaller() {
    int sequence = Runs.MAX_LENGTH * RunSequences.MAX_RUNS;
    try (LibertyCore core = new LibertyCore()) {
      core.start();
      for (int length : new int[] {1, 2, Runs.MAX_LENGTH + 1, sequence + 1, 10_000}) {
        List<List<String>> between = new ArrayList<>();
        Chain<Integer, Integer> chain = null;
        for (int i = 0; i < length; i++) {
          Chain<Integer, Integer> step =
              core.chain(
                  (Integer x) -> {
                    between.add(framesBelowCaller());
                    return x + 1;
                  });
          chain = chain == null ? step : chain.then(step);
        }
        Block<Integer, Integer> block = chain.toBlock();
        assertEquals(length, callFromHere(block, 0));
        assertEquals(length, between.size());
        int deepest = 0;
        for (List<String> frames : between) {
          assertTrue(frames.size() <= 3, "length " + length + ": frames " + frames);
          deepest = Math.max(deepest, frames.size());
        }
        if (length == 1) {
          assertEquals(1, deepest, "a chain of one block is one frame below: " + between);
        }
      }
    }
  }

  /**
   * Templates other than links are the core's generic blocks, one step each: an if/else between
   * two blocks makes a run of three steps, and its branch runs under the generic if/else block.
   */
  @Test
  void aTemplateIsTheCoresGenericBlockAndOneStep() {
    List<List<String>> between = new ArrayList<>();
    try (LibertyCore core = new LibertyCore()) {
      core.start();
      Block<Integer, Integer> block =
          core.chain((Integer x) -> x + 1)
              .then(
                  core.ifThenElse(
                      (Integer x) -> x > 0,
                      core.chain(
                          (Integer x) -> {
                            between.add(framesBelowCaller());
                            return x * 10;
                          }),
                      core.chain((Integer x) -> -x)))
              .then((Integer x) -> x + 2)
              .toBlock();
      assertEquals(Runs.Run3.class, block.getClass(), "three steps: block, if/else, block");
      assertEquals(22, callFromHere(block, 1));
      assertEquals(List.of(
              Runs.Run1.class.getName() + ".process",
              "dev.prime.IfThenElseBlock.process",
              Runs.Run3.class.getName() + ".process"),
          between.get(0),
          "the branch's own run, under the generic if/else block, under the chain's run");
    }
  }

  /** Calls {@code block}: the frame {@link #framesBelowCaller()} counts down to. */
  private static int callFromHere(Block<Integer, Integer> block, int input) {
    return block.process(input);
  }

  /** The frames between the calling block's lambda and {@link #callFromHere}. */
  private static List<String> framesBelowCaller() {
    List<StackWalker.StackFrame> frames = StackWalker.getInstance().walk(f -> f.skip(2).toList());
    List<String> between = new ArrayList<>();
    for (StackWalker.StackFrame frame : frames) {
      if (frame.getMethodName().equals("callFromHere")) {
        return between;
      }
      between.add(frame.getClassName() + "." + frame.getMethodName());
    }
    throw new AssertionError("not called through callFromHere: " + frames);
  }

  private static Class<?> shapeOf(int length) {
    try (LibertyCore core = new LibertyCore()) {
      Chain<Integer, Integer> chain = core.chain((Integer x) -> x + 1);
      for (int i = 1; i < length; i++) {
        chain = chain.then((Integer x) -> x + 1);
      }
      core.start();
      Block<Integer, Integer> block = chain.toBlock();
      assertEquals(length, block.process(0));
      return block.getClass();
    }
  }

  /** {@code length} named chains adding one, the one at {@code failing} throwing instead. */
  private static Chain<Long, Long> adders(
      LibertyCore core, int length, int failing, RuntimeException boom) {
    Chain<Long, Long> chain = null;
    for (int i = 0; i < length; i++) {
      Block<Long, Long> block =
          i == failing
              ? x -> {
                throw boom;
              }
              : x -> x + 1;
      Chain<Long, Long> step = core.chain(name(length, failing, i), block);
      chain = chain == null ? step : chain.then(step);
    }
    return chain;
  }

  private static String name(int length, int failing, int position) {
    return "l" + length + "-f" + failing + "-" + position;
  }

  private static Block<List<Integer>, List<Integer>> appending(int value) {
    return list -> {
      List<Integer> next = new ArrayList<>(list);
      next.add(value);
      return next;
    };
  }
}
