package dev.prime;

/**
 * The outputs of a union of 5 chains, in the order the chains were given.
 *
 * @param first output of chain 1
 * @param second output of chain 2
 * @param third output of chain 3
 * @param fourth output of chain 4
 * @param fifth output of chain 5
 * @param <A> type of first
 * @param <B> type of second
 * @param <C> type of third
 * @param <D> type of fourth
 * @param <E> type of fifth
 */
public record Tuple5<A, B, C, D, E>(A first, B second, C third, D fourth, E fifth) {}
