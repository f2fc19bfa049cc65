package dev.prime;

/**
 * The outputs of a union of 2 chains, in the order the chains were given.
 *
 * @param first output of chain 1
 * @param second output of chain 2
 * @param <A> type of first
 * @param <B> type of second
 */
public record Tuple2<A, B>(A first, B second) {}
