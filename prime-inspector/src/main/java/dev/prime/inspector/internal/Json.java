package dev.prime.inspector.internal;

import java.util.Collection;
import java.util.Map;

/**
 * Writes JSON text: just what the inspector's answers need (objects, arrays, strings, numbers,
 * booleans, null). Strings are escaped so that the text can also sit inside an HTML page or a
 * server-sent event line: {@code <}, {@code >}, {@code &}, line separators and every control
 * character are written as {@code \}{@code uXXXX}.
 */
public final class Json {
  private final StringBuilder out = new StringBuilder(256);
  private boolean needsComma;

  /** {@return the text written so far} */
  @Override
  public String toString() {
    return out.toString();
  }

  /** Opens an object; returns this. */
  public Json beginObject() {
    separate();
    out.append('{');
    needsComma = false;
    return this;
  }

  /** Closes an object; returns this. */
  public Json endObject() {
    out.append('}');
    needsComma = true;
    return this;
  }

  /** Opens an array; returns this. */
  public Json beginArray() {
    separate();
    out.append('[');
    needsComma = false;
    return this;
  }

  /** Closes an array; returns this. */
  public Json endArray() {
    out.append(']');
    needsComma = true;
    return this;
  }

  /**
   * Writes an object member's name; its value follows.
   *
   * @param name the member's name
   * @return this
   */
  public Json name(String name) {
    separate();
    string(out, name);
    out.append(':');
    needsComma = false;
    return this;
  }

  /**
   * Writes a string, or null.
   *
   * @param value the string
   * @return this
   */
  public Json value(String value) {
    separate();
    if (value == null) {
      out.append("null");
    } else {
      string(out, value);
    }
    needsComma = true;
    return this;
  }

  /**
   * Writes a number; NaN and the infinities, which JSON has not, as null.
   *
   * @param value the number
   * @return this
   */
  public Json value(double value) {
    separate();
    if (Double.isNaN(value) || Double.isInfinite(value)) {
      out.append("null");
    } else if (value == Math.rint(value) && Math.abs(value) < 1e15) {
      out.append((long) value);
    } else {
      out.append(value);
    }
    needsComma = true;
    return this;
  }

  /**
   * Writes a whole number.
   *
   * @param value the number
   * @return this
   */
  public Json value(long value) {
    separate();
    out.append(value);
    needsComma = true;
    return this;
  }

  /**
   * Writes a boolean.
   *
   * @param value the boolean
   * @return this
   */
  public Json value(boolean value) {
    separate();
    out.append(value);
    needsComma = true;
    return this;
  }

  /**
   * Writes null.
   *
   * @return this
   */
  public Json nullValue() {
    separate();
    out.append("null");
    needsComma = true;
    return this;
  }

  /**
   * Writes an array of strings.
   *
   * @param values the strings
   * @return this
   */
  public Json strings(Collection<String> values) {
    beginArray();
    values.forEach(this::value);
    return endArray();
  }

  /**
   * Writes an object of numbers.
   *
   * @param values the numbers by name
   * @return this
   */
  public Json numbers(Map<String, Double> values) {
    beginObject();
    values.forEach((name, number) -> name(name).value(number));
    return endObject();
  }

  private void separate() {
    if (needsComma) {
      out.append(',');
    }
  }

  private static void string(StringBuilder out, String text) {
    out.append('"');
    for (int i = 0; i < text.length(); i++) {
      char c = text.charAt(i);
      switch (c) {
        case '"' -> out.append("\\\"");
        case '\\' -> out.append("\\\\");
        case '\n' -> out.append("\\n");
        case '\r' -> out.append("\\r");
        case '\t' -> out.append("\\t");
        default -> {
          if (c < 0x20 || c == '<' || c == '>' || c == '&' || c == '\u2028' || c == '\u2029'
              || Character.isSurrogate(c) && !validSurrogate(text, i)) {
            out.append(String.format("\\u%04x", (int) c));
          } else {
            out.append(c);
          }
        }
      }
    }
    out.append('"');
  }

  private static boolean validSurrogate(String text, int i) {
    char c = text.charAt(i);
    if (Character.isHighSurrogate(c)) {
      return i + 1 < text.length() && Character.isLowSurrogate(text.charAt(i + 1));
    }
    return i > 0 && Character.isHighSurrogate(text.charAt(i - 1));
  }
}
