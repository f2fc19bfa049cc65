package dev.prime.internal;

import java.util.HashMap;
import java.util.HashSet;
import java.util.Map;
import java.util.Set;

/**
 * The names of a core's chains and sources: unique, deterministic in declaration order (so
 * processes that declare the same topology agree on them), and safe as parts of Redis keys.
 * Thread-safe.
 */
public final class Names {
  /** Longest derived name kept as is; longer ones become {@code kind-N}. */
  private static final int MAX_DERIVED = 120;

  private final Set<String> taken = new HashSet<>();
  private final Map<String, Integer> counters = new HashMap<>();

  /**
   * Claims a name given by the user.
   *
   * @param name the name
   * @return the name
   * @throws IllegalArgumentException if it is invalid or already taken
   */
  public synchronized String claim(String name) {
    check(name);
    if (!taken.add(name)) {
      throw new IllegalArgumentException(
          "the name '" + name + "' is already used in this core; give each chain and source its"
              + " own name");
    }
    return name;
  }

  /**
   * Generates a fresh name {@code kind-N}.
   *
   * @param kind what is named: chain, source, ...
   * @return the new name
   */
  public synchronized String fresh(String kind) {
    while (true) {
      int n = counters.merge(kind, 1, Integer::sum);
      String name = kind + "-" + n;
      if (taken.add(name)) {
        return name;
      }
    }
  }

  /**
   * Claims a name derived from other names (such as {@code a>b} for a link), falling back to a
   * fresh {@code kind-N} if it is too long, and adding a suffix if it is taken.
   *
   * @param derived the preferred name
   * @param kind fallback kind
   * @return the claimed name
   */
  public synchronized String derived(String derived, String kind) {
    if (derived.length() > MAX_DERIVED || !valid(derived)) {
      return fresh(kind);
    }
    if (taken.add(derived)) {
      return derived;
    }
    for (int i = 2; ; i++) {
      String name = derived + "#" + i;
      if (taken.add(name)) {
        return name;
      }
    }
  }

  /**
   * Releases a name claimed for a declaration that failed, so it can be claimed again. A fresh
   * {@code kind-N} that was the last of its kind gives its number back too, so that the next
   * fresh name is the one it would have been without the failed declaration (release the names of
   * a failed declaration latest first).
   *
   * @param name a claimed name
   */
  public synchronized void release(String name) {
    if (!taken.remove(name)) {
      return;
    }
    int dash = name.lastIndexOf('-');
    if (dash > 0) {
      String kind = name.substring(0, dash);
      Integer last = counters.get(kind);
      if (last != null && name.substring(dash + 1).equals(String.valueOf(last))) {
        counters.put(kind, last - 1);
      }
    }
  }

  private static boolean valid(String name) {
    if (name.isEmpty() || name.length() > 200) {
      return false;
    }
    for (int i = 0; i < name.length(); i++) {
      char c = name.charAt(i);
      if (Character.isWhitespace(c)
          || Character.isSpaceChar(c) // the no-break spaces, which isWhitespace lets through
          || Character.isISOControl(c) || c == '{' || c == '}') {
        return false;
      }
    }
    return true;
  }

  private static void check(String name) {
    if (name == null) {
      throw new NullPointerException("name must not be null");
    }
    if (!valid(name)) {
      throw new IllegalArgumentException(
          "the name '" + name + "' is invalid: use 1 to 200 characters with no whitespace, control"
              + " characters or braces");
    }
  }
}
