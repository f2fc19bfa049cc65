package dev.prime;

import java.util.Objects;

/**
 * The checks a link, template or service makes of the chains and sources it is given, before it
 * consumes anything: a declaration that fails them changes nothing (every chain given to it stays
 * usable). They run inside the declaration ({@link DeclarationLock}), so no claim on another
 * thread can come between a check and the claim.
 */
final class DeclarationChecks {
  private DeclarationChecks() {}

  /**
   * Checks that chains given to {@code core}'s declaration are usable.
   *
   * @throws NullPointerException if a chain is {@code null}, naming which
   * @throws ChainAlreadyUsedException if a chain was consumed before or is given twice
   * @throws CoreClosedException if the core or a chain's core is closed
   */
  static void requireChains(PrimeCore core, Chain<?, ?>... chains) {
    core.ensureOpen();
    for (int i = 0; i < chains.length; i++) {
      Chain<?, ?> chain = chains[i];
      if (chain == null) {
        throw new NullPointerException("chain argument " + (i + 1) + " must not be null");
      }
      for (int j = 0; j < i; j++) {
        if (chains[j] == chain) {
          throw new ChainAlreadyUsedException(chain.name());
        }
      }
      if (chain.core().isClosed()) {
        throw new CoreClosedException(chain.core().name());
      }
      if (chain instanceof ModelChain<?, ?, ?> known && known.used()) {
        throw new ChainAlreadyUsedException(chain.name());
      }
    }
  }

  /**
   * Checks that a source given to {@code core}'s declaration is usable.
   *
   * @throws NullPointerException if it is {@code null}
   * @throws CoreClosedException if the core or the source's core is closed
   */
  static void requireSource(PrimeCore core, Source<?> source) {
    core.ensureOpen();
    Objects.requireNonNull(source, "source must not be null");
    if (source.core().isClosed()) {
      throw new CoreClosedException(source.core().name());
    }
  }
}
