package dev.prime.conformance;

import dev.prime.ValueCodec;
import java.io.ByteArrayInputStream;
import java.io.ByteArrayOutputStream;
import java.io.IOException;
import java.io.NotSerializableException;
import java.io.ObjectInputStream;
import java.io.ObjectOutputStream;
import java.io.Serializable;
import java.io.UncheckedIOException;

/**
 * The kit's copying codec for media without one of their own: Java serialization, in memory
 * only (the bytes never leave the process, so reading them is safe). Refuses values that are not
 * {@link Serializable} with {@link IllegalArgumentException}, as a real codec refuses a type it
 * does not know.
 */
public final class SerializingCodec implements ValueCodec {

  /** The codec. */
  public static final SerializingCodec INSTANCE = new SerializingCodec();

  private SerializingCodec() {}

  @Override
  public byte[] encode(Object value) {
    if (!(value instanceof Serializable)) {
      throw new IllegalArgumentException(
          value.getClass().getName() + " cannot be copied: it is not Serializable");
    }
    ByteArrayOutputStream bytes = new ByteArrayOutputStream();
    try (ObjectOutputStream out = new ObjectOutputStream(bytes)) {
      out.writeObject(value);
    } catch (NotSerializableException e) {
      throw new IllegalArgumentException("a part of the value is not Serializable: " + e, e);
    } catch (IOException e) {
      throw new UncheckedIOException(e);
    }
    return bytes.toByteArray();
  }

  @Override
  public Object decode(byte[] bytes) {
    try (ObjectInputStream in = new ObjectInputStream(new ByteArrayInputStream(bytes))) {
      return in.readObject();
    } catch (IOException e) {
      throw new UncheckedIOException(e);
    } catch (ClassNotFoundException e) {
      throw new IllegalStateException(e);
    }
  }

  @Override
  public String toString() {
    return "SerializingCodec";
  }
}
