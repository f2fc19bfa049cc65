package dev.prime;

import java.util.concurrent.atomic.AtomicInteger;

/**
 * What {@link PrimeCore#isolate} gives: makes the users of one shared block, each a chain node of
 * its own ({@code shared@1}, {@code shared@2}, ...) compiled by the core's model compiler.
 *
 * @param <I> input type
 * @param <O> output type
 */
final class IsolatedChain<I, O> implements Isolated<I, O> {
  private final PrimeCore core;
  private final String sharedNode;
  private final String sharedName;
  private final Block<I, O> shared;
  private final AtomicInteger users = new AtomicInteger();

  IsolatedChain(PrimeCore core, String sharedNode, String sharedName, Block<I, O> shared) {
    this.core = core;
    this.sharedNode = sharedNode;
    this.sharedName = sharedName;
    this.shared = shared;
  }

  @Override
  public String name() {
    return sharedName;
  }

  @Override
  public Chain<I, O> newUser() {
    core.ensureOpen();
    return DeclarationLock.run(
        core,
        () ->
            core.model()
                .chain(
                    core.topologyRecorder()
                        .isolatedUser(sharedNode, sharedName, users.incrementAndGet(), shared)));
  }
}
