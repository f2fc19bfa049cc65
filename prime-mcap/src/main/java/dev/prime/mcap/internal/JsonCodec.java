package dev.prime.mcap.internal;

import com.fasterxml.jackson.annotation.JsonAutoDetect;
import com.fasterxml.jackson.annotation.JsonInclude;
import com.fasterxml.jackson.annotation.PropertyAccessor;
import com.fasterxml.jackson.databind.DeserializationFeature;
import com.fasterxml.jackson.databind.JavaType;
import com.fasterxml.jackson.databind.ObjectMapper;
import com.fasterxml.jackson.databind.json.JsonMapper;
import com.fasterxml.jackson.datatype.jdk8.Jdk8Module;
import java.lang.reflect.Type;

/**
 * The one Jackson configuration of prime-mcap. No default typing: a value's type comes from
 * its channel, never from the bytes, so a file cannot make the reader instantiate a class.
 * Records are read and written through their components (fields), never through getter-like
 * methods, so the JSON has exactly the properties the JSON Schema lists. Nulls are left out
 * (a record's reference components are not "required" in the schema); a primitive component
 * missing from the JSON is an error instead of a silent zero.
 */
public final class JsonCodec {
  private JsonCodec() {}

  /** The shared, thread-safe mapper. */
  public static final ObjectMapper MAPPER =
      JsonMapper.builder()
          .addModule(new Jdk8Module())
          .visibility(PropertyAccessor.ALL, JsonAutoDetect.Visibility.NONE)
          .visibility(PropertyAccessor.FIELD, JsonAutoDetect.Visibility.ANY)
          .visibility(PropertyAccessor.CREATOR, JsonAutoDetect.Visibility.ANY)
          .defaultPropertyInclusion(JsonInclude.Value.construct(JsonInclude.Include.NON_NULL, JsonInclude.Include.NON_NULL))
          .enable(DeserializationFeature.FAIL_ON_NULL_FOR_PRIMITIVES)
          .enable(DeserializationFeature.FAIL_ON_UNKNOWN_PROPERTIES)
          .build();

  /**
   * @param type a Java type
   * @return Jackson's view of it
   */
  public static JavaType javaType(Type type) {
    return MAPPER.getTypeFactory().constructType(type);
  }
}
