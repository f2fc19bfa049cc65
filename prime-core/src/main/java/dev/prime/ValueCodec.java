package dev.prime;

/**
 * Turns values into bytes and back: what a media that carries values between processes does to
 * every value, and what {@link dev.prime.CoreConfig.Builder#copyValues(ValueCodec)} makes the
 * in-memory media do, so that a test on one of them fails the way a distributed media would (on a
 * value mutated after it was handed over, or on a type the codec refuses).
 *
 * <p>Optimus's codecs implement it ({@code KryoCodec.standard()} can be given as is).
 *
 * <h2>Contract</h2>
 * <ul>
 *   <li><b>Copies.</b> {@code decode(encode(v))} is a value equal to {@code v} that shares no
 *       mutable state with it.
 *   <li><b>Threading.</b> Both methods are called concurrently from many threads.
 *   <li><b>Nulls.</b> Neither method sees {@code null}.
 *   <li><b>Exceptions.</b> {@link #encode} throws {@link IllegalArgumentException} for a value it
 *       refuses, with a message that says how to allow it; {@link #decode} throws an unchecked
 *       exception for bytes it cannot read.
 * </ul>
 */
public interface ValueCodec {

  /**
   * Encodes one value.
   *
   * @param value never {@code null}
   * @return the bytes
   * @throws IllegalArgumentException if the value's type is not allowed
   */
  byte[] encode(Object value);

  /**
   * Decodes bytes written by {@link #encode}.
   *
   * @param bytes the bytes
   * @return a new value
   */
  Object decode(byte[] bytes);

  /**
   * A copy of {@code value} made by encoding and decoding it.
   *
   * @param value the value; {@code null} is returned as is
   * @param <T> its type
   * @return the copy
   */
  @SuppressWarnings("unchecked")
  default <T> T copy(T value) {
    return value == null ? null : (T) decode(encode(value));
  }
}
