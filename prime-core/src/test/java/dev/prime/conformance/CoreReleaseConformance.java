package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.lang.ref.Reference;
import java.lang.ref.ReferenceQueue;
import java.lang.ref.WeakReference;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;

/**
 * A program can create, start and close cores as often as it likes (docs/architecture.md,
 * <i>Lifecycle of a core</i>): a robot that reconfigures its diagram, a test suite. Each closed
 * core, the blocks of its chains and whatever classes the media generated for them become
 * unreachable once the program lets go of them, although the event blocks its sources read and
 * its forks publish to (an encoder's driver, a logger) live on and are used by the next core.
 */
public interface CoreReleaseConformance extends ConformanceBase {

  /** Cores made, used and closed one after the other. */
  int RELEASED_CORES = 12;

  /** Rounds of {@code System.gc()} at most, each waiting at most 250 ms for a release. */
  int GC_ROUNDS = 40;

  @Test
  default void closedCoresTheirBlocksAndGeneratedClassesAreReleasedWhileTheirEventBlocksLiveOn()
      throws InterruptedException {
    EventBlock<Integer> encoder = new EventBlock<>();
    EventBlock<Integer> log = new EventBlock<>();
    AtomicInteger logged = new AtomicInteger();
    log.subscribe(x -> logged.incrementAndGet()); // the program's own subscriber, for good
    ReferenceQueue<Object> released = new ReferenceQueue<>();
    Map<Reference<Object>, String> kept = new LinkedHashMap<>();
    for (int i = 0; i < RELEASED_CORES; i++) {
      useAndClose(i, encoder, log, released, kept);
    }
    assertEquals(RELEASED_CORES, logged.get(), "values the forks published to the logger");

    for (int round = 0; round < GC_ROUNDS && !kept.isEmpty(); round++) {
      System.gc();
      for (Reference<?> gone = released.remove(250); gone != null; gone = released.poll()) {
        kept.remove(gone);
      }
    }
    assertEquals(
        List.of(),
        new ArrayList<>(kept.values()),
        "still reachable after " + GC_ROUNDS + " collections, though closed and dropped");

    PrimeCore next = newCore();
    try (next) {
      Reader<Integer> reader =
          next.source("encoder", encoder).then(next.chain("next", (Integer x) -> -x)).reader();
      next.start();
      encoder.publish(7);
      assertEquals(-7, takeOrFail(reader), "the encoder feeds the next core");
    }
  }

  /**
   * Declares, starts, uses and closes a core whose source reads {@code encoder} and whose fork
   * publishes to {@code log}; keeps only weak references to the core, a block of its chains, the
   * block a chain became and, if the media generated its class, that class and its loader.
   */
  private void useAndClose(
      int i,
      EventBlock<Integer> encoder,
      EventBlock<Integer> log,
      ReferenceQueue<Object> released,
      Map<Reference<Object>, String> kept)
      throws InterruptedException {
    PrimeCore core = newCore();
    List<Integer> seen = new ArrayList<>(); // a block with state of its own: a new one per core
    Block<Integer, Integer> scale =
        x -> {
          seen.add(x);
          return x * 10;
        };
    Block<Integer, Integer> call;
    try (core) {
      Reader<Integer> doubled =
          core.source("encoder", encoder)
              .then(core.chain("double", (Integer x) -> 2 * x).then((Integer x) -> x + 1))
              .reader();
      call =
          core.fork(
                  core.chain("scale", scale).then(core.chain("offset", (Integer x) -> x + 1)), log)
              .toBlock();
      core.start();
      encoder.publish(i);
      assertEquals(2 * i + 1, takeOrFail(doubled), "core " + i + " read the encoder");
      assertEquals(10 * i + 1, call.process(i), "core " + i + "'s call");
      assertEquals(List.of(i), seen, "what the stateful block of core " + i + " saw");
    }
    track(core, "core " + core.name(), released, kept);
    track(scale, "a block of " + core.name(), released, kept);
    track(call, "the block 'scale>offset' of " + core.name() + " became", released, kept);
    Class<?> type = call.getClass();
    if (generated(type)) {
      track(type, "the class generated for it, " + type.getName(), released, kept);
      track(type.getClassLoader(), "its class loader, " + type.getClassLoader(), released, kept);
    }
  }

  private static void track(
      Object value,
      String what,
      ReferenceQueue<Object> released,
      Map<Reference<Object>, String> kept) {
    kept.put(new WeakReference<>(value, released), what);
  }

  /**
   * Whether a class was made at run time in a class loader of its own: its loader is neither the
   * kit's nor one the kit's loader delegates to (the media's and the user's classes, and lambdas,
   * which live in their declaring class's loader, are not).
   */
  private static boolean generated(Class<?> type) {
    ClassLoader loader = type.getClassLoader();
    for (ClassLoader known = CoreReleaseConformance.class.getClassLoader();
        known != null;
        known = known.getParent()) {
      if (known == loader) {
        return false;
      }
    }
    return loader != null;
  }
}
