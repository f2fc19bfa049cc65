package dev.prime;

/**
 * One chain shared by several users, never run concurrently: each user gets a chain of its own
 * (chains are single use), and calls through all of them are serialised.
 *
 * @param <I> input type
 * @param <O> output type
 * @see PrimeCore#isolate(Chain)
 */
public interface Isolated<I, O> {

  /** {@return the name of the shared chain} */
  String name();

  /**
   * Creates a chain for one more user of the shared chain.
   *
   * @return a new chain, named {@code <name>@<n>}
   */
  Chain<I, O> newUser();
}
