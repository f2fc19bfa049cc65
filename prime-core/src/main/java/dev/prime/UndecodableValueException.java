package dev.prime;

/**
 * A value of an in-memory source whose copy the core's codec ({@link
 * CoreConfig.Builder#copyValues}) could not decode: the codec broke its contract ({@code
 * decode(encode(v))} must give {@code v}). The value is skipped; a service that read it reports
 * this to the error handler, with the encoded bytes as the input, and goes on with the next value.
 */
final class UndecodableValueException extends PrimeException {
  private static final long serialVersionUID = 1L;

  private final transient byte[] encoded;

  /**
   * @param reader who read the value: {@code service '<name>'} or {@code a reader}
   * @param source the source the value was published to
   * @param codec the codec that failed
   * @param encoded the bytes it could not decode
   * @param cause what the codec threw
   */
  UndecodableValueException(
      String reader, String source, ValueCodec codec, byte[] encoded, Throwable cause) {
    super(
        reader
            + " could not decode a value of source '"
            + source
            + "' with codec "
            + codec
            + ": "
            + cause
            + "; the value is skipped. A codec given to CoreConfig.copyValues must decode every"
            + " value it encodes (decode(encode(v)) equals v): fix the codec, or leave the value's"
            + " type out of what it accepts so that its encode refuses it",
        cause);
    this.encoded = encoded;
  }

  /** The bytes the codec could not decode (null once serialized). */
  byte[] encoded() {
    return encoded;
  }
}
