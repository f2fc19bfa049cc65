package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Repeat;
import java.util.ArrayList;
import java.util.List;
import java.util.function.Function;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;

/**
 * A failed link changes nothing: every link and template checks all its chains before it
 * consumes any, so giving it a used chain throws {@link ChainAlreadyUsedException} naming that
 * chain and leaves every other chain usable.
 */
public interface AtomicLinkConformance extends ConformanceBase {

  /** One refused call: given the used chain and fresh chains made on demand, it links them. */
  @FunctionalInterface
  interface Refused {
    void link(Chain<Integer, Integer> used, Function<String, Chain<Integer, Integer>> fresh);
  }

  @Test
  default void aLinkOrTemplateRefusingAUsedChainConsumesNothing() {
    List<Refused> refusals =
        List.of(
            (used, fresh) -> fresh.apply("first").then(used),
            (used, fresh) -> used.core().link(fresh.apply("first"), used),
            (used, fresh) -> used.core().link(used, fresh.apply("second")),
            (used, fresh) -> used.core().ifThenElse(x -> true, fresh.apply("then"), used),
            (used, fresh) -> used.core().ifThenElse(x -> true, used, fresh.apply("else")),
            (used, fresh) -> used.core().forEach(used),
            (used, fresh) -> used.core().union(fresh.apply("a"), used),
            (used, fresh) -> used.core().union(fresh.apply("a"), fresh.apply("b"), used),
            (used, fresh) ->
                used.core().union(fresh.apply("a"), fresh.apply("b"), fresh.apply("c"), used),
            (used, fresh) ->
                used.core()
                    .union(
                        fresh.apply("a"), fresh.apply("b"), fresh.apply("c"), fresh.apply("d"), used),
            (used, fresh) -> used.core().fork(used, new EventBlock<Integer>()),
            (used, fresh) -> used.core().guard(x -> true, used, x -> x),
            (used, fresh) -> used.core().isolate(used),
            (used, fresh) ->
                used.core().repeater(used, (Integer in, Integer out, List<Void> none) -> Repeat.stop(out)),
            (used, fresh) ->
                used.core()
                    .repeater(
                        used,
                        used.core().source(new EventBlock<String>()),
                        (Integer in, Integer out, List<String> seen) -> Repeat.stop(out)),
            (used, fresh) -> used.core().link(used.core().source(new EventBlock<Integer>()), used),
            (used, fresh) -> used.core().source(new EventBlock<Integer>()).then(used));
    for (int i = 0; i < refusals.size(); i++) {
      Refused refused = refusals.get(i);
      String what = "refusal " + (i + 1);
      try (PrimeCore core = newCore()) {
        Chain<Integer, Integer> used = core.chain("used", x -> x);
        used.toBlock();
        List<Chain<Integer, Integer>> others = new ArrayList<>();
        Executable call =
            () ->
                refused.link(
                    used,
                    role -> {
                      Chain<Integer, Integer> chain = core.chain(role, (Integer x) -> x + 1);
                      others.add(chain);
                      return chain;
                    });
        ChainAlreadyUsedException e = assertThrows(ChainAlreadyUsedException.class, call, what);
        assertEquals("used", e.chainName(), what + ": the used chain is blamed");
        core.start();
        for (Chain<Integer, Integer> other : others) {
          assertEquals(
              2, other.toBlock().process(1), what + ": chain '" + other.name() + "' is still usable");
        }
      }
    }
  }
}
