package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
import dev.prime.ChainFailedException;
import dev.prime.CoreClosedException;
import dev.prime.EventBlock;
import dev.prime.Tuple2;
import dev.prime.Tuple3;
import dev.prime.Tuple4;
import dev.prime.Tuple5;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.Test;

/** The fused templates compute what the generic ones do, and fail the same way. */
class RadiantTemplatesTest {
  private final RadiantCore core = new RadiantCore();

  @AfterEach
  void close() {
    core.close();
  }

  static <T> Block<T, T> throwing(RuntimeException failure) {
    return x -> {
      throw failure;
    };
  }

  @Test
  void aSingleChainRunsItsBlock() {
    Block<Integer, Integer> twice = core.chain((Integer x) -> x * 2).toBlock();
    assertEquals(14, twice.process(7));
    assertTrue(twice.toString().contains("chain-1"), twice.toString());
  }

  @Test
  void linkedChainsRunInOrder() {
    Block<String, String> block =
        core.chain((String s) -> s + "a").then((String s) -> s + "b").then((String s) -> s + "c")
            .toBlock();
    assertEquals("xabc", block.process("x"));
  }

  @Test
  void ifThenElseChoosesTheBranchByTheCondition() {
    Block<Integer, String> block =
        core.ifThenElse(
                (Integer x) -> x > 0,
                core.chain((Integer x) -> "positive " + x),
                core.chain((Integer x) -> "other " + x))
            .toBlock();
    assertEquals("positive 3", block.process(3));
    assertEquals("other -3", block.process(-3));
  }

  @Test
  void forEachMapsEveryElementInOrder() {
    Block<List<Integer>, List<Integer>> block =
        core.forEach(core.chain((Integer x) -> x * 10).then((Integer x) -> x + 1)).toBlock();
    assertEquals(List.of(11, 21, 31), block.process(List.of(1, 2, 3)));
    assertEquals(List.of(), block.process(List.of()));
  }

  @Test
  void forEachKeepsNullOutputs() {
    Block<List<Integer>, List<Object>> block =
        core.forEach(core.chain((Integer x) -> x > 1 ? null : (Object) x)).toBlock();
    assertEquals(Arrays.asList(1, null), block.process(List.of(1, 2)));
  }

  @Test
  void nestedForEachLoopsKeepTheirOwnState() {
    Block<List<List<Integer>>, List<List<Integer>>> block =
        core.forEach(core.forEach(core.chain((Integer x) -> -x))).toBlock();
    assertEquals(
        List.of(List.of(-1, -2), List.of(), List.of(-3)),
        block.process(List.of(List.of(1, 2), List.of(), List.of(3))));
  }

  @Test
  void unionsOfTwoToFiveGiveTuplesInOrder() {
    assertEquals(
        new Tuple2<>(2, "1"),
        core.union(core.chain((Integer x) -> x + 1), core.chain((Integer x) -> "" + x))
            .toBlock()
            .process(1));
    assertEquals(
        new Tuple3<>(1, 2, 3),
        core.union(
                core.chain((Integer x) -> x), core.chain((Integer x) -> x + 1),
                core.chain((Integer x) -> x + 2))
            .toBlock()
            .process(1));
    assertEquals(
        new Tuple4<>(1, 2, 3, 4),
        core.union(
                core.chain((Integer x) -> x), core.chain((Integer x) -> x + 1),
                core.chain((Integer x) -> x + 2), core.chain((Integer x) -> x + 3))
            .toBlock()
            .process(1));
    assertEquals(
        new Tuple5<>(1, 2, 3, 4, 5),
        core.union(
                core.chain((Integer x) -> x), core.chain((Integer x) -> x + 1),
                core.chain((Integer x) -> x + 2), core.chain((Integer x) -> x + 3),
                core.chain((Integer x) -> x + 4))
            .toBlock()
            .process(1));
  }

  @Test
  void forkPublishesNonNullOutputsAndReturnsThem() {
    EventBlock<Integer> events = new EventBlock<>();
    List<Integer> seen = new ArrayList<>();
    events.subscribe(seen::add);
    Block<Integer, Integer> block =
        core.fork(core.chain((Integer x) -> x < 0 ? null : x * 2), events).toBlock();
    assertEquals(4, block.process(2));
    assertNull(block.process(-1));
    assertEquals(6, block.process(3));
    assertEquals(List.of(4, 6), seen);
  }

  @Test
  void guardRunsTheChainOnlyForInputsThatPass() {
    List<Integer> ran = new ArrayList<>();
    Block<Integer, String> block =
        core.guard(
                (Integer x) -> x % 2 == 0,
                core.chain(
                    (Integer x) -> {
                      ran.add(x);
                      return "even " + x;
                    }),
                (Integer x) -> "skipped " + x)
            .toBlock();
    assertEquals("even 2", block.process(2));
    assertEquals("skipped 3", block.process(3));
    assertEquals(List.of(2), ran);
  }

  @Test
  void genericTemplatesStillWorkAsLeaves() {
    Block<Integer, Integer> block =
        core.isolate(core.chain((Integer x) -> x + 1)).newUser().then((Integer x) -> x * 3)
            .toBlock();
    assertEquals(9, block.process(2));
  }

  @Test
  void aChainIsSingleUse() {
    Chain<Integer, Integer> chain = core.chain((Integer x) -> x);
    chain.then((Integer x) -> x);
    ChainAlreadyUsedException e = assertThrows(ChainAlreadyUsedException.class, chain::toBlock);
    assertEquals(chain.name(), e.chainName());
    Chain<Integer, Integer> other = core.chain((Integer x) -> x);
    assertThrows(ChainAlreadyUsedException.class, () -> core.union(other, other));
  }

  @Test
  void aFailingLeafIsNamedWithTheOriginalAsCause() {
    IllegalStateException boom = new IllegalStateException("boom");
    Block<Integer, Integer> block =
        core.chain("ok", (Integer x) -> x)
            .then(
                core.chain("failing", RadiantTemplatesTest.<Integer>throwing(boom)))
            .then(core.chain("after", (Integer x) -> x))
            .toBlock();
    ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process(1));
    assertEquals("failing", e.chainName());
    assertSame(boom, e.getCause());
  }

  @Test
  void failuresOfTemplateCodeNameTheTemplateChain() {
    Chain<Integer, String> branch =
        core.ifThenElse(
            (Integer x) -> {
              throw new ArithmeticException("bad condition");
            },
            core.chain((Integer x) -> "a"),
            core.chain((Integer x) -> "b"));
    String name = branch.name();
    Block<Integer, String> block = branch.toBlock();
    ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process(1));
    assertEquals(name, e.chainName());
    assertInstanceOf(ArithmeticException.class, e.getCause());

    Chain<List<Integer>, List<Integer>> loop = core.forEach(core.chain((Integer x) -> x));
    String loopName = loop.name();
    Block<List<Integer>, List<Integer>> loopBlock = loop.toBlock();
    ChainFailedException nullInput =
        assertThrows(ChainFailedException.class, () -> loopBlock.process(null));
    assertEquals(loopName, nullInput.chainName());
    assertInstanceOf(NullPointerException.class, nullInput.getCause());

    Chain<Integer, Integer> guard =
        core.guard(
            (Integer x) -> false,
            core.chain((Integer x) -> x),
            (Integer x) -> {
              throw new UnsupportedOperationException("no substitute");
            });
    String guardName = guard.name();
    Block<Integer, Integer> guardBlock = guard.toBlock();
    ChainFailedException substitute =
        assertThrows(ChainFailedException.class, () -> guardBlock.process(1));
    assertEquals(guardName, substitute.chainName());
  }

  @Test
  void errorsAreWrappedButVirtualMachineErrorsAndCoreClosedPassUnwrapped() {
    AssertionError assertion = new AssertionError("an error is wrapped like an exception");
    Block<Integer, Integer> error =
        core.chain(
                "asserting",
                (Block<Integer, Integer>)
                    x -> {
                      throw assertion;
                    })
            .toBlock();
    ChainFailedException wrapped = assertThrows(ChainFailedException.class, () -> error.process(1));
    assertEquals("asserting", wrapped.chainName());
    assertSame(assertion, wrapped.getCause());
    OutOfMemoryError oom = new OutOfMemoryError("a VirtualMachineError is not wrapped");
    Block<Integer, Integer> vm =
        core.chain(
                (Block<Integer, Integer>)
                    x -> {
                      throw oom;
                    })
            .toBlock();
    assertSame(oom, assertThrows(OutOfMemoryError.class, () -> vm.process(1)));
    Block<Integer, Integer> closed =
        core.chain(RadiantTemplatesTest.<Integer>throwing(new CoreClosedException("elsewhere")))
            .toBlock();
    assertThrows(CoreClosedException.class, () -> closed.process(1));
  }

  @Test
  void usingAClosedCoreFails() {
    Chain<Integer, Integer> chain = core.chain((Integer x) -> x);
    core.close();
    assertThrows(CoreClosedException.class, chain::toBlock);
    assertThrows(CoreClosedException.class, () -> core.chain((Integer x) -> x));
  }

  @Test
  void badArgumentsAreRejectedAtTheCall() {
    Chain<Integer, Integer> chain = core.chain((Integer x) -> x);
    assertThrows(NullPointerException.class, () -> core.ifThenElse(null, chain, chain));
    assertThrows(NullPointerException.class, () -> core.fork(chain, null));
    assertThrows(NullPointerException.class, () -> core.guard(x -> true, chain, null));
    assertThrows(NullPointerException.class, () -> core.link(chain, null));
  }
}
