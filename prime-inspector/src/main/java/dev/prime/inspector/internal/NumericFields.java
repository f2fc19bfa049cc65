package dev.prime.inspector.internal;

import java.lang.reflect.Method;
import java.lang.reflect.RecordComponent;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;

/**
 * The numbers in a value, for plotting: a number is one field ({@code value}); a boolean is 0 or
 * 1; a record gives its numeric components by name, nested records as {@code pose.x}, down to a
 * few levels and at most {@value #MAX_FIELDS} fields. Anything else (strings, lists, classes that
 * are not records) gives nothing. Record components are read through their public accessors; a
 * record whose accessor cannot be called from here (a package its module does not export) gives
 * nothing for that component.
 */
public final class NumericFields {
  /** The most fields one value gives. */
  static final int MAX_FIELDS = 12;
  private static final int MAX_DEPTH = 3;

  private final Map<Class<?>, List<Accessor>> accessors = new ConcurrentHashMap<>();

  private record Accessor(String name, Method method) {}

  /**
   * The numeric fields of a value.
   *
   * @param value a recorded value
   * @return its numbers by field name, in component order; empty if it has none
   */
  public Map<String, Double> of(Object value) {
    Map<String, Double> fields = new LinkedHashMap<>();
    collect("", value, 0, fields);
    return fields;
  }

  private void collect(String prefix, Object value, int depth, Map<String, Double> fields) {
    if (fields.size() >= MAX_FIELDS || value == null) {
      return;
    }
    String name = prefix.isEmpty() ? "value" : prefix;
    if (value instanceof Number number) {
      fields.put(name, number.doubleValue());
    } else if (value instanceof Boolean bool) {
      fields.put(name, bool ? 1.0 : 0.0);
    } else if (value.getClass().isRecord() && depth < MAX_DEPTH) {
      for (Accessor accessor : accessors.computeIfAbsent(value.getClass(), NumericFields::find)) {
        Object component;
        try {
          component = accessor.method().invoke(value);
        } catch (ReflectiveOperationException | RuntimeException e) {
          continue; // an accessor that fails or throws gives no field
        }
        collect(prefix.isEmpty() ? accessor.name() : prefix + "." + accessor.name(), component,
            depth + 1, fields);
      }
    }
  }

  private static List<Accessor> find(Class<?> type) {
    List<Accessor> found = new ArrayList<>();
    for (RecordComponent component : type.getRecordComponents()) {
      Method method = component.getAccessor();
      try {
        method.setAccessible(true);
      } catch (RuntimeException e) {
        if (!publiclyReachable(type)) {
          continue;
        }
      }
      found.add(new Accessor(component.getName(), method));
    }
    return List.copyOf(found);
  }

  private static boolean publiclyReachable(Class<?> type) {
    return java.lang.reflect.Modifier.isPublic(type.getModifiers())
        && type.getModule().isExported(type.getPackageName());
  }
}
