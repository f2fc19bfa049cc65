package dev.prime.radiant.internal;

/**
 * Hands a generated class its constants (the blocks, predicates and event blocks it calls) while
 * its static initializer runs.
 *
 * <p>Design note. A fused class keeps every block it calls in a {@code static final} field, so the
 * JIT treats each call's receiver as a constant of a known class and inlines it without relying on
 * a type profile. Static finals can only be written by the class's own {@code <clinit>}, which
 * calls {@link #take()}; {@link #initialize} puts the values in a thread-local slot, initializes
 * the class on the same thread, and clears the slot, so nothing outlives the call and classes
 * compiled concurrently on different threads never see each other's values.
 */
public final class FusedConstants {
  private static final ThreadLocal<Object[]> PENDING = new ThreadLocal<>();

  private FusedConstants() {}

  /**
   * Called by a generated class's static initializer: the values it was compiled with.
   *
   * @return the values, in field order
   * @throws IllegalStateException if no class is being initialized by this thread
   */
  public static Object[] take() {
    Object[] values = PENDING.get();
    if (values == null) {
      throw new IllegalStateException(
          "a fused Radiant class is initialized only by the Radiant compiler that made it");
    }
    PENDING.remove();
    return values;
  }

  /**
   * Initializes {@code type}, whose static initializer takes {@code values}.
   *
   * @param type a generated class, not yet initialized
   * @param values its constants
   */
  static void initialize(Class<?> type, Object[] values) {
    PENDING.set(values);
    try {
      Class.forName(type.getName(), true, type.getClassLoader());
    } catch (ClassNotFoundException e) {
      throw new IllegalStateException("a generated class cannot be found by its own loader", e);
    } finally {
      PENDING.remove();
    }
  }
}
