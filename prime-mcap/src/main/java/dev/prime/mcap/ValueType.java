package dev.prime.mcap;

import com.fasterxml.jackson.databind.JavaType;
import com.fasterxml.jackson.core.JsonParser;
import com.fasterxml.jackson.core.JsonToken;
import com.fasterxml.jackson.databind.ObjectReader;
import com.fasterxml.jackson.databind.ObjectWriter;
import com.fasterxml.jackson.databind.node.ObjectNode;
import dev.prime.mcap.internal.JsonCodec;
import dev.prime.mcap.internal.JsonSchemaGenerator;
import java.lang.reflect.ParameterizedType;
import java.lang.reflect.Type;
import java.nio.charset.StandardCharsets;
import java.util.Objects;

/**
 * The Java type of the values on one MCAP channel, with the JSON Schema that describes them.
 * The type decides how values are written and read; nothing in a file names a Java class.
 *
 * <p>For a plain class use {@link #of(Class)}; for a generic type, an anonymous subclass keeps
 * the type arguments: {@code new ValueType<Tuple2<Double, String>>() {}}.
 *
 * <p>Supported: records (one JSON property per component), enums (their constant names),
 * primitives and their boxes, {@code String}, {@code BigInteger}, {@code BigDecimal},
 * {@code byte[]} (base64), arrays, {@code List}/{@code Set}/{@code Collection}, {@code Map}
 * with String, enum or integer keys, {@code Optional} (the value or null) and Jackson's
 * {@code JsonNode} (any JSON), nested freely. Prime's {@code Tuple2..5} are records and its
 * {@code Token} an enum, so they are covered. Anything else (an interface, {@code Object}, a
 * class that is not a record) is refused when the {@code ValueType} is made, with the path to
 * the offending part.
 *
 * <p>For Foxglove, every message is a JSON object: a record is its own object, and any other
 * type's value is wrapped as {@code {"value": ...}} (its schema an object with that one
 * property); {@link #fromJson} unwraps it. Schemas have no {@code $ref}: a record that contains
 * itself is described {@value dev.prime.mcap.internal.JsonSchemaGenerator#RECURSION_DEPTH} levels
 * deep and any JSON below (such values are written and read in full).
 *
 * @param <T> the Java type
 */
public abstract class ValueType<T> {
  private static final byte[] WRAP_OPEN = "{\"value\":".getBytes(StandardCharsets.UTF_8);

  private final Type type;
  private final JavaType javaType;
  private final String jsonSchema;
  private final ObjectWriter writer;
  private final ObjectReader reader;
  private final boolean wrapped; // messages are {"value": ...}: Foxglove wants objects

  /**
   * For an anonymous subclass: {@code new ValueType<List<Pose>>() {}} captures
   * {@code List<Pose>}.
   *
   * @throws IllegalArgumentException if the type is not supported (the message says which part)
   */
  protected ValueType() {
    Type superclass = getClass().getGenericSuperclass();
    if (!(superclass instanceof ParameterizedType)) {
      throw new IllegalArgumentException(
          "new ValueType<...>() {} needs a type argument: write new ValueType<MyType>() {}");
    }
    this.type = ((ParameterizedType) superclass).getActualTypeArguments()[0];
    this.javaType = JsonCodec.javaType(type);
    this.jsonSchema = schemaText(javaType);
    this.writer = JsonCodec.MAPPER.writerFor(javaType);
    this.reader = JsonCodec.MAPPER.readerFor(javaType);
    this.wrapped = JsonSchemaGenerator.isWrapped(javaType);
  }

  private ValueType(Type type) {
    this.type = type;
    this.javaType = JsonCodec.javaType(type);
    this.jsonSchema = schemaText(javaType);
    this.writer = JsonCodec.MAPPER.writerFor(javaType);
    this.reader = JsonCodec.MAPPER.readerFor(javaType);
    this.wrapped = JsonSchemaGenerator.isWrapped(javaType);
  }

  private static final class Plain<T> extends ValueType<T> {
    Plain(Type type) {
      super(type);
    }
  }

  private static String schemaText(JavaType javaType) {
    ObjectNode schema = JsonSchemaGenerator.schemaOf(javaType);
    return schema.toPrettyString();
  }

  /**
   * @param type a non-generic class (for generic types use an anonymous subclass)
   * @param <T> the type
   * @return its value type
   * @throws IllegalArgumentException if the type is not supported (the message says which part)
   * @throws NullPointerException if {@code type} is null
   */
  public static <T> ValueType<T> of(Class<T> type) {
    Objects.requireNonNull(type, "type must not be null: give the values' class");
    if (type.getTypeParameters().length > 0) {
      throw new IllegalArgumentException(
          type.getName() + " is generic: name its type arguments with new ValueType<"
              + type.getSimpleName() + "<...>>() {}");
    }
    return new Plain<>(type);
  }

  /**
   * @param type any {@link Type} (for instance a record component's generic type)
   * @return its value type
   * @throws IllegalArgumentException if the type is not supported (the message says which part)
   * @throws NullPointerException if {@code type} is null
   */
  public static ValueType<?> ofType(Type type) {
    Objects.requireNonNull(type, "type must not be null: give the values' type");
    return new Plain<>(type);
  }

  /** @return the Java type */
  public Type type() {
    return type;
  }

  /** @return the type's name with its type arguments, the MCAP schema name */
  public String name() {
    return javaType.toCanonical();
  }

  /** @return the JSON Schema (draft 2020-12) of the values, as JSON text */
  public String jsonSchema() {
    return jsonSchema;
  }

  /**
   * @param value a value
   * @return its JSON, UTF-8
   * @throws IllegalArgumentException if Jackson cannot write it
   */
  public byte[] toJson(T value) {
    try {
      byte[] json = writer.writeValueAsBytes(value);
      if (!wrapped) {
        return json;
      }
      byte[] out = new byte[WRAP_OPEN.length + json.length + 1];
      System.arraycopy(WRAP_OPEN, 0, out, 0, WRAP_OPEN.length);
      System.arraycopy(json, 0, out, WRAP_OPEN.length, json.length);
      out[out.length - 1] = '}';
      return out;
    } catch (java.io.IOException e) {
      throw new IllegalArgumentException("cannot write " + name() + " as JSON: " + e.getMessage(), e);
    }
  }

  /**
   * @param json UTF-8 JSON of one value
   * @return the value
   * @throws IllegalArgumentException if the JSON is not a value of this type (the message says why)
   */
  public T fromJson(byte[] json) {
    try {
      if (!wrapped) {
        return reader.readValue(json);
      }
      try (JsonParser parser = JsonCodec.MAPPER.createParser(json)) {
        if (parser.nextToken() != JsonToken.START_OBJECT
            || parser.nextToken() != JsonToken.FIELD_NAME
            || !"value".equals(parser.currentName())) {
          throw notWrapped(json);
        }
        parser.nextToken();
        T value = reader.readValue(parser);
        if (parser.nextToken() != JsonToken.END_OBJECT || parser.nextToken() != null) {
          throw notWrapped(json);
        }
        return value;
      }
    } catch (com.fasterxml.jackson.core.JsonProcessingException e) {
      String text = new String(json, 0, Math.min(json.length, 200), StandardCharsets.UTF_8);
      throw new IllegalArgumentException(
          "JSON " + text + (json.length > 200 ? "..." : "") + " is not a " + name() + ": "
              + e.getOriginalMessage(), e);
    } catch (java.io.IOException e) {
      throw new java.io.UncheckedIOException(e);
    }
  }

  private IllegalArgumentException notWrapped(byte[] json) {
    String text = new String(json, 0, Math.min(json.length, 200), StandardCharsets.UTF_8);
    return new IllegalArgumentException(
        "JSON " + text + (json.length > 200 ? "..." : "") + " is not a " + name()
            + ": a value that is not a record is written as {\"value\": ...}, an object with"
            + " that one property");
  }

  @Override
  public boolean equals(Object o) {
    return o instanceof ValueType && ((ValueType<?>) o).javaType.equals(javaType);
  }

  @Override
  public int hashCode() {
    return javaType.hashCode();
  }

  @Override
  public String toString() {
    return "ValueType[" + name() + "]";
  }
}
