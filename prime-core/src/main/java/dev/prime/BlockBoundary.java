package dev.prime;

import dev.prime.internal.ServiceThreads;

/**
 * What the core's generic blocks do between two parts they run one after the other on one thread
 * (the blocks of a link, a condition and its branch, the parts of a union, the elements of a
 * for-each): the flag a part set on the thread of a service of an open core is cleared, so the
 * next part starts as it would on a thread of its own (see {@link
 * dev.prime.spi.LinkedBlocks}). Costs a read of the flag and a branch.
 */
final class BlockBoundary {
  private BlockBoundary() {}

  /** Between two parts: clears the flag the first set on a service's thread. */
  static void crossed() {
    if (Thread.currentThread().isInterrupted()) {
      ServiceThreads.clearOwnInterrupt();
    }
  }
}
