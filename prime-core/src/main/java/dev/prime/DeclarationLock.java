package dev.prime;

import java.util.ArrayList;
import java.util.List;
import java.util.TreeMap;
import java.util.function.Supplier;

/**
 * Runs a declaration of a core (a link, template, service, or a chain's {@link Chain#toBlock()})
 * under the declaration lock of that core and of every core whose chain it takes.
 *
 * <p>Design note. A core's declaration lock is the monitor of its {@link TopologyRecorder}
 * ({@link TopologyRecorder#declare}): a declaration checks its chains, compiles and claims them
 * holding it, so a claim on another thread cannot slip in between. A declaration may take another
 * core's chain (through that chain's {@code toBlock()}, which takes that core's lock), so two
 * cores declaring with each other's chains at once could each hold one lock and wait for the
 * other. To rule that out, the locks of every core a declaration involves are taken up front in
 * one global order (the order the cores were created); the nested {@code toBlock()} then finds
 * its lock already held (monitors are reentrant).
 */
final class DeclarationLock {
  private DeclarationLock() {}

  /**
   * Runs {@code declaration} atomically for {@code core} ({@link TopologyRecorder#declare}),
   * holding the declaration locks of {@code core} and of the cores of {@code chains}.
   *
   * @param core the declaring core
   * @param declaration checks, records, compiles and claims
   * @param chains the chains it takes (nulls and user-made chains without a core are skipped:
   *     the declaration refuses them itself)
   */
  static <T> T run(PrimeCore core, Supplier<T> declaration, Chain<?, ?>... chains) {
    TreeMap<Long, PrimeCore> cores = new TreeMap<>();
    cores.put(core.creationOrder(), core);
    for (Chain<?, ?> chain : chains) {
      PrimeCore other = chain == null ? null : chain.core();
      if (other != null) {
        cores.put(other.creationOrder(), other);
      }
    }
    TopologyRecorder recorder = core.topologyRecorder();
    if (cores.size() == 1) {
      return recorder.declare(declaration);
    }
    return inOrder(new ArrayList<>(cores.values()), 0, () -> recorder.declare(declaration));
  }

  private static <T> T inOrder(List<PrimeCore> cores, int next, Supplier<T> body) {
    if (next == cores.size()) {
      return body.get();
    }
    synchronized (cores.get(next).topologyRecorder()) {
      return inOrder(cores, next + 1, body);
    }
  }
}
