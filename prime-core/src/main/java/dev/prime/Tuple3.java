package dev.prime;

/**
 * The outputs of a union of 3 chains, in the order the chains were given.
 *
 * @param first output of chain 1
 * @param second output of chain 2
 * @param third output of chain 3
 * @param <A> type of first
 * @param <B> type of second
 * @param <C> type of third
 */
public record Tuple3<A, B, C>(A first, B second, C third) {}
