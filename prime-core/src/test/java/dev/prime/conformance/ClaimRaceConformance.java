package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
import dev.prime.PrimeCore;
import dev.prime.Tuple3;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import java.util.function.Supplier;
import org.junit.jupiter.api.Test;

/**
 * A chain is claimed once, atomically with the declaration that claims it: {@link Chain#toBlock()}
 * on one thread and a link or template taking the same chain on another never both succeed, and
 * the one that loses consumed nothing (the link's other chains stay usable).
 */
public interface ClaimRaceConformance extends ConformanceBase {

  /**
   * A chain of another core whose {@link Chain#toBlock()} waits until {@code open} opens: a
   * template taking it holds the point between checking its chains and claiming them for as long
   * as the test wants.
   */
  static Chain<Integer, Integer> gated(
      Chain<Integer, Integer> real, CountDownLatch entered, CountDownLatch open) {
    return new Chain<>() {
      @Override
      public PrimeCore core() {
        return real.core();
      }

      @Override
      public String name() {
        return real.name();
      }

      @Override
      public Block<Integer, Integer> toBlock() {
        entered.countDown();
        try {
          if (!open.await(60, TimeUnit.SECONDS)) {
            throw new IllegalStateException("the gate was never opened");
          }
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
          throw new IllegalStateException(e);
        }
        return real.toBlock();
      }
    };
  }

  @Test
  default void toBlockDuringATemplateThatTakesTheSameChainLeavesNothingHalfConsumed()
      throws Exception {
    try (PrimeCore core = newCore();
        PrimeCore other = newCore()) {
      Chain<Integer, Integer> first = core.chain("first", x -> x + 1);
      Chain<Integer, Integer> contested = core.chain("contested", x -> x + 2);
      CountDownLatch entered = new CountDownLatch(1);
      CountDownLatch open = new CountDownLatch(1);
      Chain<Integer, Integer> gate = gated(other.chain("gate", x -> x + 3), entered, open);
      AtomicReference<Object> byUnion = new AtomicReference<>();
      AtomicReference<Object> byCall = new AtomicReference<>();
      CountDownLatch go = new CountDownLatch(1);
      Thread union = racer(go, () -> core.union(first, contested, gate), byUnion);
      go.countDown();
      assertTrue(entered.await(patience().toMillis(), TimeUnit.MILLISECONDS), "union under way");
      // the union has checked its chains and waits for the gate: claim one of them meanwhile
      CountDownLatch callGo = new CountDownLatch(1);
      Thread call = racer(callGo, contested::toBlock, byCall);
      callGo.countDown();
      // give the call the time to finish if nothing holds it (it does not, before the fix), then
      // let the union go on; the outcome must be consistent whichever way it went
      call.join(300);
      open.countDown();
      union.join(patience().toMillis());
      call.join(patience().toMillis());
      assertFalse(union.isAlive() || call.isAlive(), "the union or the call did not return");
      boolean unionWon = byUnion.get() instanceof Chain<?, ?>;
      boolean callWon = byCall.get() instanceof Block<?, ?>;
      assertTrue(unionWon ^ callWon, "exactly one claims 'contested': " + byUnion + ", " + byCall);
      Object lost = unionWon ? byCall.get() : byUnion.get();
      assertInstanceOf(ChainAlreadyUsedException.class, lost, "the loser is refused");
      assertEquals("contested", ((ChainAlreadyUsedException) lost).chainName());
      core.start();
      other.start();
      if (unionWon) {
        @SuppressWarnings("unchecked")
        Chain<Integer, Tuple3<Integer, Integer, Integer>> made =
            (Chain<Integer, Tuple3<Integer, Integer, Integer>>) byUnion.get();
        assertEquals(new Tuple3<>(2, 3, 4), made.toBlock().process(1));
      } else {
        assertEquals(2, first.toBlock().process(1), "the refused union left 'first' usable");
      }
    }
  }

  @Test
  default void toBlockRacingALinkOfTheSameChainClaimsItOnce() throws Exception {
    int trials = 200;
    long deadline = System.nanoTime() + patience().toNanos();
    try (PrimeCore core = newCore()) {
      List<Chain<Integer, Integer>> refusedLinks = new ArrayList<>();
      List<Block<Integer, Integer>> calls = new ArrayList<>();
      List<Chain<Integer, Integer>> links = new ArrayList<>();
      for (int trial = 0; trial < trials && System.nanoTime() < deadline; trial++) {
        Chain<Integer, Integer> first = core.chain("first-" + trial, x -> x + 1);
        Chain<Integer, Integer> contested = core.chain("contested-" + trial, x -> x * 10);
        CountDownLatch go = new CountDownLatch(1);
        AtomicReference<Object> byLink = new AtomicReference<>();
        AtomicReference<Object> byCall = new AtomicReference<>();
        Thread link = racer(go, () -> core.link(first, contested), byLink);
        Thread call = racer(go, contested::toBlock, byCall);
        go.countDown();
        link.join(patience().toMillis());
        call.join(patience().toMillis());
        assertFalse(link.isAlive() || call.isAlive(), "trial " + trial + ": a claim did not return");
        boolean linkWon = byLink.get() instanceof Chain<?, ?>;
        boolean callWon = byCall.get() instanceof Block<?, ?>;
        assertTrue(linkWon ^ callWon, "trial " + trial + ": one claim wins: " + byLink + ", " + byCall);
        Object lost = linkWon ? byCall.get() : byLink.get();
        assertTrue(
            lost instanceof ChainAlreadyUsedException used
                && used.chainName().equals(contested.name()),
            "trial " + trial + ": the loser is refused for the contested chain: " + lost);
        if (linkWon) {
          @SuppressWarnings("unchecked")
          Chain<Integer, Integer> made = (Chain<Integer, Integer>) byLink.get();
          links.add(made);
        } else {
          @SuppressWarnings("unchecked")
          Block<Integer, Integer> block = (Block<Integer, Integer>) byCall.get();
          calls.add(block);
          refusedLinks.add(first);
        }
      }
      core.start();
      for (Chain<Integer, Integer> first : refusedLinks) {
        assertEquals(2, first.toBlock().process(1), first.name() + " is still usable");
      }
      for (Block<Integer, Integer> block : calls) {
        assertEquals(10, block.process(1));
      }
      for (Chain<Integer, Integer> made : links) {
        assertEquals(20, made.toBlock().process(1));
      }
    }
  }

  /** A started thread that runs {@code claim} once {@code go} opens and keeps what it gave. */
  private static Thread racer(
      CountDownLatch go, Supplier<Object> claim, AtomicReference<Object> result) {
    Thread thread =
        new Thread(
            () -> {
              try {
                if (go.await(60, TimeUnit.SECONDS)) {
                  result.set(claim.get());
                }
              } catch (RuntimeException | InterruptedException e) {
                result.set(e);
              }
            },
            "kit-claimer");
    thread.setDaemon(true);
    thread.start();
    return thread;
  }
}
