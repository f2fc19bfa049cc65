package dev.prime;

import java.util.Arrays;
import java.util.List;
import java.util.Objects;

/**
 * Gives one input to several blocks, in order, and gathers their outputs into a tuple.
 *
 * <p>Build one with the {@code of} factories.
 *
 * @param <I> input type
 * @param <T> tuple type
 */
final class UnionBlock<I, T> implements Block<I, T> {

  /** Assembles a tuple from the parts' outputs. */
  @FunctionalInterface
  private interface TupleMaker<T> {
    T make(Object[] outputs);
  }

  private final Block<? super I, ?>[] parts;
  private final TupleMaker<T> maker;

  private UnionBlock(TupleMaker<T> maker, List<Block<? super I, ?>> parts) {
    for (int i = 0; i < parts.size(); i++) {
      Objects.requireNonNull(parts.get(i), "union part " + (i + 1) + " must not be null");
    }
    @SuppressWarnings({"unchecked", "rawtypes"})
    Block<? super I, ?>[] array = parts.toArray(new Block[0]);
    this.parts = array;
    this.maker = maker;
  }

  /**
   * @param a first part
   * @param b second part
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @return the union
   */
  @SuppressWarnings("unchecked")
  static <I, A, B> Block<I, Tuple2<A, B>> of(Block<I, A> a, Block<I, B> b) {
    return new UnionBlock<>(o -> new Tuple2<>((A) o[0], (B) o[1]), Arrays.<Block<? super I, ?>>asList(a, b));
  }

  /**
   * @param a first part
   * @param b second part
   * @param c third part
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @param <C> output of c
   * @return the union
   */
  @SuppressWarnings("unchecked")
  static <I, A, B, C> Block<I, Tuple3<A, B, C>> of(
      Block<I, A> a, Block<I, B> b, Block<I, C> c) {
    return new UnionBlock<>(o -> new Tuple3<>((A) o[0], (B) o[1], (C) o[2]), Arrays.<Block<? super I, ?>>asList(a, b, c));
  }

  /**
   * @param a first part
   * @param b second part
   * @param c third part
   * @param d fourth part
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @param <C> output of c
   * @param <D> output of d
   * @return the union
   */
  @SuppressWarnings("unchecked")
  static <I, A, B, C, D> Block<I, Tuple4<A, B, C, D>> of(
      Block<I, A> a, Block<I, B> b, Block<I, C> c, Block<I, D> d) {
    return new UnionBlock<>(
        o -> new Tuple4<>((A) o[0], (B) o[1], (C) o[2], (D) o[3]),
        Arrays.<Block<? super I, ?>>asList(a, b, c, d));
  }

  /**
   * @param a first part
   * @param b second part
   * @param c third part
   * @param d fourth part
   * @param e fifth part
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @param <C> output of c
   * @param <D> output of d
   * @param <E> output of e
   * @return the union
   */
  @SuppressWarnings("unchecked")
  static <I, A, B, C, D, E> Block<I, Tuple5<A, B, C, D, E>> of(
      Block<I, A> a, Block<I, B> b, Block<I, C> c, Block<I, D> d, Block<I, E> e) {
    return new UnionBlock<>(
        o -> new Tuple5<>((A) o[0], (B) o[1], (C) o[2], (D) o[3], (E) o[4]),
        Arrays.<Block<? super I, ?>>asList(a, b, c, d, e));
  }

  @Override
  public T process(I input) {
    Object[] outputs = new Object[parts.length];
    for (int i = 0; i < parts.length; i++) {
      outputs[i] = parts[i].process(input);
    }
    return maker.make(outputs);
  }
}
