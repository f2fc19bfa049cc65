package dev.prime.test.internal;

import dev.prime.test.CoreSetup;
import dev.prime.test.Media;
import dev.prime.test.PrimeTest;
import java.lang.reflect.Constructor;
import java.lang.reflect.InvocationTargetException;
import java.lang.reflect.Method;
import java.lang.reflect.Modifier;
import java.util.Arrays;
import java.util.function.Supplier;
import java.util.stream.Stream;
import org.junit.jupiter.api.extension.ExtensionConfigurationException;
import org.junit.jupiter.api.extension.ExtensionContext;
import org.junit.jupiter.api.extension.TestTemplateInvocationContext;
import org.junit.jupiter.api.extension.TestTemplateInvocationContextProvider;
import org.junit.platform.commons.support.AnnotationSupport;

/**
 * Turns a {@link PrimeTest} method into one run per media; each run's {@link MediaRun} makes,
 * injects and closes its core. Registered by {@code @PrimeTest}; not to be used directly.
 */
public final class PrimeTestExtension implements TestTemplateInvocationContextProvider {

  /** Where the extension keeps the test class's Redis and slow link. */
  static final ExtensionContext.Namespace NAMESPACE =
      ExtensionContext.Namespace.create(PrimeTestExtension.class);

  /** The JUnit configuration parameter naming a Redis for Optimus runs instead of an embedded one. */
  static final String REDIS_PARAMETER = "prime.test.redis";

  /** Made by JUnit. */
  public PrimeTestExtension() {}

  @Override
  public boolean supportsTestTemplate(ExtensionContext context) {
    return context.getTestMethod().flatMap(m -> AnnotationSupport.findAnnotation(m, PrimeTest.class)).isPresent();
  }

  @Override
  public Stream<TestTemplateInvocationContext> provideTestTemplateInvocationContexts(
      ExtensionContext context) {
    Method method = context.getRequiredTestMethod();
    PrimeTest test = AnnotationSupport.findAnnotation(method, PrimeTest.class).orElseThrow();
    Media[] media = test.media();
    if (media.length == 0) {
      throw new ExtensionConfigurationException(
          "@PrimeTest(media = {}) on " + method.getName() + "() names no media, so the test would"
              + " never run: name at least one (LIBERTY, RADIANT, OPTIMUS, OPTIMUS_SLOW_LINK) or leave"
              + " media out for LIBERTY, RADIANT and OPTIMUS");
    }
    Supplier<CoreSetup> setup = setupMaker(test.setup(), method);
    return Arrays.stream(media).map(m -> new MediaRun(m, setup));
  }

  /** Checks once that the setup class can be made, then makes one per run. */
  private static Supplier<CoreSetup> setupMaker(Class<? extends CoreSetup> type, Method method) {
    if (type == CoreSetup.class) {
      return () -> new CoreSetup() {};
    }
    String where = "@PrimeTest(setup = " + type.getSimpleName() + ".class) on " + method.getName() + "()";
    if (type.isInterface() || Modifier.isAbstract(type.getModifiers())) {
      throw new ExtensionConfigurationException(
          where + ": " + type.getName() + " is abstract; name a concrete class implementing CoreSetup");
    }
    if (type.getEnclosingClass() != null && !Modifier.isStatic(type.getModifiers())) {
      throw new ExtensionConfigurationException(
          where + ": " + type.getName() + " is an inner class; make it static so it can be made"
              + " without an instance of " + type.getEnclosingClass().getSimpleName());
    }
    Constructor<? extends CoreSetup> constructor;
    try {
      constructor = type.getDeclaredConstructor();
      constructor.setAccessible(true);
    } catch (NoSuchMethodException e) {
      throw new ExtensionConfigurationException(
          where + ": " + type.getName() + " has no constructor without parameters; add one (it may"
              + " be private)", e);
    }
    return () -> {
      try {
        return constructor.newInstance();
      } catch (InvocationTargetException e) {
        throw new ExtensionConfigurationException(
            where + ": the constructor of " + type.getName() + " threw " + e.getCause(), e.getCause());
      } catch (ReflectiveOperationException e) {
        throw new ExtensionConfigurationException(
            where + ": cannot make a " + type.getName() + ": " + e, e);
      }
    };
  }
}
