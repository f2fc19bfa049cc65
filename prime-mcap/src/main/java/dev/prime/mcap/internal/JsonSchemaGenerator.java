package dev.prime.mcap.internal;

import com.fasterxml.jackson.databind.JavaType;
import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.node.ArrayNode;
import com.fasterxml.jackson.databind.node.JsonNodeFactory;
import com.fasterxml.jackson.databind.node.ObjectNode;
import java.lang.reflect.RecordComponent;
import java.math.BigDecimal;
import java.math.BigInteger;
import java.util.ArrayDeque;
import java.util.Collection;
import java.util.Deque;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.OptionalDouble;
import java.util.OptionalInt;
import java.util.OptionalLong;
import java.util.Set;

/**
 * Builds the JSON Schema (draft 2020-12) of a value type, matching what {@link JsonCodec}
 * writes: records are objects with one property per component, enums strings with their
 * constants, byte arrays base64 strings, collections and arrays arrays, maps objects, Optional
 * the content or null. Foxglove wants every message to be a JSON object and does not follow
 * {@code $ref}, so: a type that is not a record is wrapped ({@link #isWrapped}: the message is
 * {@code {"value": ...}} and the schema an object with that one required property), and schemas
 * are inlined, with no {@code $ref}. A record that contains itself is inlined {@value
 * #RECURSION_DEPTH} levels deep; below that its schema is {@code {}} (any JSON, with a
 * description saying so): such values still validate, but Foxglove sees no fields under that
 * depth. Any other type is refused with the path to it, so a channel never records values its
 * schema does not describe.
 */
public final class JsonSchemaGenerator {
  private static final JsonNodeFactory NODES = JsonNodeFactory.instance;

  /** What the refusal message lists. */
  public static final String SUPPORTED =
      "records, enums, primitives and their boxes, String, BigInteger, BigDecimal, byte[],"
          + " arrays, List/Set/Collection, Map with String, enum or integer keys, Optional,"
          + " OptionalInt/Long/Double and JsonNode";

  /** How many levels of a record that contains itself a schema describes. */
  public static final int RECURSION_DEPTH = 4;

  private final Deque<JavaType> visiting = new ArrayDeque<>();

  private JsonSchemaGenerator() {}

  /**
   * @param type a value type
   * @return whether its messages are {@code {"value": ...}} (every type but a record)
   */
  public static boolean isWrapped(JavaType type) {
    return !type.getRawClass().isRecord();
  }

  /**
   * @param type the value type
   * @return its JSON Schema
   * @throws IllegalArgumentException naming the unsupported part of the type
   */
  public static ObjectNode schemaOf(JavaType type) {
    JsonSchemaGenerator generator = new JsonSchemaGenerator();
    ObjectNode body = generator.schema(type, "value");
    ObjectNode schema = NODES.objectNode();
    schema.put("$schema", "https://json-schema.org/draft/2020-12/schema");
    schema.put("title", type.toCanonical());
    if (isWrapped(type)) {
      schema.put("type", "object");
      schema.putObject("properties").set("value", body);
      schema.putArray("required").add("value");
      schema.put("additionalProperties", false);
    } else {
      schema.setAll(body);
    }
    return schema;
  }

  private ObjectNode schema(JavaType type, String path) {
    Class<?> raw = type.getRawClass();
    if (JsonNode.class.isAssignableFrom(raw)) {
      return NODES.objectNode();
    }
    if (raw == boolean.class || raw == Boolean.class) {
      return typed("boolean");
    }
    if (raw == byte.class || raw == Byte.class) {
      return range(typed("integer"), Byte.MIN_VALUE, Byte.MAX_VALUE);
    }
    if (raw == short.class || raw == Short.class) {
      return range(typed("integer"), Short.MIN_VALUE, Short.MAX_VALUE);
    }
    if (raw == int.class || raw == Integer.class) {
      return range(typed("integer"), Integer.MIN_VALUE, Integer.MAX_VALUE);
    }
    if (raw == long.class || raw == Long.class) {
      return range(typed("integer"), Long.MIN_VALUE, Long.MAX_VALUE);
    }
    if (raw == BigInteger.class) {
      return typed("integer");
    }
    if (raw == float.class || raw == Float.class || raw == double.class || raw == Double.class
        || raw == BigDecimal.class) {
      return typed("number");
    }
    if (raw == char.class || raw == Character.class) {
      ObjectNode s = typed("string");
      s.put("minLength", 1);
      s.put("maxLength", 1);
      return s;
    }
    if (raw == String.class || raw == char[].class) {
      return typed("string");
    }
    if (raw == byte[].class) {
      ObjectNode s = typed("string");
      s.put("contentEncoding", "base64");
      return s;
    }
    if (raw.isEnum()) {
      ObjectNode s = typed("string");
      ArrayNode constants = s.putArray("enum");
      for (Object constant : raw.getEnumConstants()) {
        constants.add(((Enum<?>) constant).name());
      }
      return s;
    }
    if (raw == OptionalInt.class || raw == OptionalLong.class) {
      return nullable(typed("integer"));
    }
    if (raw == OptionalDouble.class) {
      return nullable(typed("number"));
    }
    if (raw == Optional.class) {
      return nullable(schema(type.getReferencedType(), path + ".get()"));
    }
    if (type.isArrayType()) {
      return array(schema(type.getContentType(), path + "[]"), false);
    }
    if (type.isCollectionLikeType()) {
      if (raw != List.class && raw != Set.class && raw != Collection.class) {
        throw unsupported(type, path, "declare collections as List, Set or Collection");
      }
      return array(schema(type.getContentType(), path + "[]"), raw == Set.class);
    }
    if (type.isMapLikeType()) {
      if (raw != Map.class) {
        throw unsupported(type, path, "declare maps as Map");
      }
      ObjectNode s = typed("object");
      ObjectNode keys = keySchema(type.getKeyType(), path);
      if (keys != null) {
        s.set("propertyNames", keys);
      }
      s.set("additionalProperties", schema(type.getContentType(), path + "{}"));
      return s;
    }
    if (raw.isRecord()) {
      return record(type, path);
    }
    throw unsupported(type, path, "record its fields in a record");
  }

  private ObjectNode record(JavaType type, String path) {
    long depth = visiting.stream().filter(type::equals).count();
    if (depth >= RECURSION_DEPTH) {
      ObjectNode any = NODES.objectNode();
      any.put(
          "description",
          type.toCanonical() + " nested deeper than " + RECURSION_DEPTH
              + " levels: not described (recursive records are inlined to a bounded depth)");
      return any;
    }
    visiting.push(type);
    ObjectNode s = typed("object");
    s.put("title", type.toCanonical());
    ObjectNode properties = s.putObject("properties");
    ArrayNode required = s.putArray("required");
    for (RecordComponent component : type.getRawClass().getRecordComponents()) {
      JavaType componentType =
          JsonCodec.MAPPER.getTypeFactory().resolveMemberType(component.getGenericType(), type.getBindings());
      properties.set(component.getName(), schema(componentType, path + "." + component.getName()));
      if (component.getType().isPrimitive()) {
        required.add(component.getName());
      }
    }
    if (required.isEmpty()) {
      s.remove("required");
    }
    s.put("additionalProperties", false);
    visiting.pop();
    return s;
  }

  private static ObjectNode keySchema(JavaType key, String path) {
    Class<?> raw = key.getRawClass();
    if (raw == String.class) {
      return null;
    }
    if (raw.isEnum()) {
      ObjectNode s = NODES.objectNode();
      ArrayNode constants = s.putArray("enum");
      for (Object constant : raw.getEnumConstants()) {
        constants.add(((Enum<?>) constant).name());
      }
      return s;
    }
    if (raw == Integer.class || raw == Long.class || raw == Short.class || raw == Byte.class
        || raw == BigInteger.class) {
      ObjectNode s = NODES.objectNode();
      s.put("pattern", "^-?[0-9]+$");
      return s;
    }
    throw new IllegalArgumentException(
        "map keys at " + path + " are " + key.toCanonical()
            + ": JSON object keys must be String, an enum or an integer type");
  }

  private static ObjectNode typed(String jsonType) {
    ObjectNode s = NODES.objectNode();
    s.put("type", jsonType);
    return s;
  }

  private static ObjectNode range(ObjectNode s, long min, long max) {
    s.put("minimum", min);
    s.put("maximum", max);
    return s;
  }

  private static ObjectNode array(ObjectNode items, boolean unique) {
    ObjectNode s = typed("array");
    s.set("items", items);
    if (unique) {
      s.put("uniqueItems", true);
    }
    return s;
  }

  private static ObjectNode nullable(ObjectNode s) {
    JsonNode type = s.get("type");
    if (type != null && type.isTextual()) {
      ObjectNode copy = s.deepCopy();
      copy.putArray("type").add(type.asText()).add("null");
      return copy;
    }
    if (s.isEmpty()) {
      return s;
    }
    ObjectNode either = NODES.objectNode();
    either.putArray("anyOf").add(s).add(typed("null"));
    return either;
  }

  private static IllegalArgumentException unsupported(JavaType type, String path, String fix) {
    return new IllegalArgumentException(
        type.toCanonical() + " (at " + path + ") is not a value type prime-mcap can record as"
            + " JSON with a schema: the supported types are " + SUPPORTED + "; " + fix + ".");
  }
}
