package dev.prime.conformance;

import dev.prime.Repeat;
import dev.prime.Tick;
import dev.prime.Tuple2;
import dev.prime.Tuple3;
import dev.prime.Tuple4;
import dev.prime.Tuple5;
import dev.prime.ValueCodec;
import java.io.ByteArrayInputStream;
import java.io.ByteArrayOutputStream;
import java.io.IOException;
import java.io.InputStream;
import java.io.NotSerializableException;
import java.io.ObjectInputStream;
import java.io.ObjectOutputStream;
import java.io.OutputStream;
import java.io.Serializable;
import java.io.UncheckedIOException;
import java.time.Instant;
import java.util.Arrays;
import java.util.List;

/**
 * The kit's copying codec for media without one of their own: Java serialization, in memory
 * only (the bytes never leave the process, so reading them is safe). Copies every {@link
 * Serializable} value and the core's own value types, which are not: the {@link Tick}s of a
 * timer, the tuples ({@link Tuple2} to {@link Tuple5}) of a zip, a union or a combineLatest, and
 * {@link Repeat}, also inside another value and with each other inside. Refuses any other value
 * with {@link IllegalArgumentException}, as a real codec refuses a type it does not know.
 *
 * <p>Design note: the core's types are written as a {@link CoreValue} (their kind and
 * components), through {@link ObjectOutputStream#replaceObject} for every object of the graph,
 * and made again from it when read, through {@link ObjectInputStream#resolveObject}.
 */
public final class SerializingCodec implements ValueCodec {

  /** The codec. */
  public static final SerializingCodec INSTANCE = new SerializingCodec();

  private SerializingCodec() {}

  @Override
  public byte[] encode(Object value) {
    if (!(value instanceof Serializable) && Kind.of(value) == null) {
      throw new IllegalArgumentException(
          value.getClass().getName() + " cannot be copied: it is not Serializable");
    }
    ByteArrayOutputStream bytes = new ByteArrayOutputStream();
    try (ObjectOutputStream out = new CoreValueOutput(bytes)) {
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
    try (ObjectInputStream in = new CoreValueInput(new ByteArrayInputStream(bytes))) {
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

  /** The core's value types that are not {@link Serializable}. */
  private enum Kind {
    TICK,
    TUPLE2,
    TUPLE3,
    TUPLE4,
    TUPLE5,
    REPEAT_AGAIN,
    REPEAT_STOP;

    /** {@return the kind of {@code value}, or {@code null} if it is none of the core's types} */
    static Kind of(Object value) {
      if (value instanceof Tick) {
        return TICK;
      } else if (value instanceof Tuple2) {
        return TUPLE2;
      } else if (value instanceof Tuple3) {
        return TUPLE3;
      } else if (value instanceof Tuple4) {
        return TUPLE4;
      } else if (value instanceof Tuple5) {
        return TUPLE5;
      } else if (value instanceof Repeat<?, ?> r) {
        return r.isAgain() ? REPEAT_AGAIN : REPEAT_STOP;
      }
      return null;
    }
  }

  /** One of the core's values as written: its kind and its components, in order. */
  private record CoreValue(Kind kind, List<Object> parts) implements Serializable {
    private static final long serialVersionUID = 1L;

    static CoreValue of(Kind kind, Object value) {
      Object[] parts =
          switch (kind) {
            case TICK -> new Object[] {((Tick) value).count(), ((Tick) value).time()};
            case TUPLE2 -> {
              Tuple2<?, ?> t = (Tuple2<?, ?>) value;
              yield new Object[] {t.first(), t.second()};
            }
            case TUPLE3 -> {
              Tuple3<?, ?, ?> t = (Tuple3<?, ?, ?>) value;
              yield new Object[] {t.first(), t.second(), t.third()};
            }
            case TUPLE4 -> {
              Tuple4<?, ?, ?, ?> t = (Tuple4<?, ?, ?, ?>) value;
              yield new Object[] {t.first(), t.second(), t.third(), t.fourth()};
            }
            case TUPLE5 -> {
              Tuple5<?, ?, ?, ?, ?> t = (Tuple5<?, ?, ?, ?, ?>) value;
              yield new Object[] {t.first(), t.second(), t.third(), t.fourth(), t.fifth()};
            }
            case REPEAT_AGAIN -> new Object[] {((Repeat<?, ?>) value).next()};
            case REPEAT_STOP -> new Object[] {((Repeat<?, ?>) value).conclusion()};
          };
      return new CoreValue(kind, Arrays.asList(parts)); // Arrays.asList: serializable, takes nulls
    }

    Object value() {
      List<Object> p = parts;
      return switch (kind) {
        case TICK -> new Tick((Long) p.get(0), (Instant) p.get(1));
        case TUPLE2 -> new Tuple2<>(p.get(0), p.get(1));
        case TUPLE3 -> new Tuple3<>(p.get(0), p.get(1), p.get(2));
        case TUPLE4 -> new Tuple4<>(p.get(0), p.get(1), p.get(2), p.get(3));
        case TUPLE5 -> new Tuple5<>(p.get(0), p.get(1), p.get(2), p.get(3), p.get(4));
        case REPEAT_AGAIN -> Repeat.again(p.get(0));
        case REPEAT_STOP -> Repeat.stop(p.get(0));
      };
    }
  }

  /** Writes each of the core's values, wherever it is in the graph, as a {@link CoreValue}. */
  private static final class CoreValueOutput extends ObjectOutputStream {
    CoreValueOutput(OutputStream out) throws IOException {
      super(out);
      enableReplaceObject(true);
    }

    @Override
    protected Object replaceObject(Object obj) {
      Kind kind = Kind.of(obj);
      return kind == null ? obj : CoreValue.of(kind, obj);
    }
  }

  /** Reads each {@link CoreValue} back as the core's value it stands for. */
  private static final class CoreValueInput extends ObjectInputStream {
    CoreValueInput(InputStream in) throws IOException {
      super(in);
      enableResolveObject(true);
    }

    @Override
    protected Object resolveObject(Object obj) {
      return obj instanceof CoreValue v ? v.value() : obj;
    }
  }
}
