package dev.prime.faults;

import dev.prime.optimus.OptimusCore;
import java.lang.reflect.InvocationTargetException;
import java.lang.reflect.Method;
import java.util.OptionalLong;

/**
 * The names of issue 9's agreed API that this suite uses and that were not yet on main when it was
 * written: {@code OptimusCore.redisResets()} (branch opt-lease) and
 * {@code dev.prime.optimus.ValueTooLargeException} (branch opt-service). They are looked up by name
 * so the suite compiles, and runs its other cases, before those branches land; a test that needs a
 * missing one fails and names the branch. Once both are on main, replace these with direct
 * references and delete this class.
 */
final class PendingApi {
  static final String VALUE_TOO_LARGE = "dev.prime.optimus.ValueTooLargeException";

  private PendingApi() {}

  /** {@code core.redisResets()}, or empty if this build has no such method. */
  static OptionalLong redisResets(OptimusCore core) {
    Method method;
    try {
      method = OptimusCore.class.getMethod("redisResets");
    } catch (NoSuchMethodException e) {
      return OptionalLong.empty();
    }
    try {
      return OptionalLong.of((Long) method.invoke(core));
    } catch (IllegalAccessException e) {
      throw new IllegalStateException("OptimusCore.redisResets() is not public", e);
    } catch (InvocationTargetException e) {
      throw new IllegalStateException("OptimusCore.redisResets() failed", e.getCause());
    }
  }

  /** Whether {@code error} is a {@code ValueTooLargeException}. */
  static boolean isValueTooLarge(Throwable error) {
    for (Class<?> type = error.getClass(); type != null; type = type.getSuperclass()) {
      if (type.getName().equals(VALUE_TOO_LARGE)) return true;
    }
    return false;
  }
}
