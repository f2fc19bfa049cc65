package dev.prime.spi;

import dev.prime.internal.ServiceThreads;

/**
 * What a media that runs the blocks of a linked chain (or the parts of a template: a condition
 * and its branch, the parts of a union, the elements of a for-each) one after another on one
 * thread does between two of them, so that every block starts as it would on a thread of its own.
 *
 * <p>A block may interrupt its own thread (it restored the flag of an {@code
 * InterruptedException} it caught). In a service, the next block of its linked chain must not
 * see that flag, as it would not where each chain is a service of its own: its first wait would
 * fail at once. {@link #between()} clears the flag on the thread of an in-process service while
 * its core is open; a synchronous caller's thread keeps its flag (the block ran on the caller's
 * thread, whose flag it set), and so does a service whose core is closing.
 *
 * <p>Design note. The normal path costs one read of the current thread's interrupt flag and a
 * branch: the generated code of a fused chain calls {@link #between()} (three bytes of bytecode)
 * between two blocks, and the JIT inlines it.
 */
public final class LinkedBlocks {
  private LinkedBlocks() {}

  /**
   * Between two blocks of a linked chain: clears the interrupt flag the first set on the thread
   * of an in-process service of an open core; does nothing if the flag is not set.
   */
  public static void between() {
    if (Thread.currentThread().isInterrupted()) {
      ServiceThreads.clearOwnInterrupt();
    }
  }
}
