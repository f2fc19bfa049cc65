package dev.prime.spi;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import java.lang.reflect.Method;
import java.lang.reflect.Modifier;
import java.util.Arrays;
import java.util.List;
import java.util.Set;
import org.junit.jupiter.api.Test;

/**
 * The media SPI stays small: what only the core itself uses is not public or protected, and the
 * generic chain compiler is a test fixture, not part of the shipped SPI.
 */
class SpiSurfaceTest {

  private static List<String> visible(Class<?> type, Set<String> names) {
    return Arrays.stream(type.getDeclaredMethods())
        .filter(m -> Modifier.isPublic(m.getModifiers()) || Modifier.isProtected(m.getModifiers()))
        .map(Method::getName)
        .filter(names::contains)
        .toList();
  }

  @Test
  void theCoreOffersMediaNoUnusedHelpers() {
    assertEquals(
        List.of(), visible(PrimeCore.class, Set.of("newSource", "derivedName", "runService")));
  }

  @Test
  void aChainsConsumptionIsNotPublic() {
    assertEquals(List.of(), visible(AbstractChain.class, Set.of("consumeAsPart")));
    for (Method m : AbstractChain.class.getDeclaredMethods()) {
      if (m.getName().equals("isUsed")) {
        assertTrue(!Modifier.isPublic(m.getModifiers()), "isUsed is for subclasses only");
      }
    }
  }

  @Test
  void theGenericChainCompilerIsATestFixture() {
    String where =
        GenericChainCompiler.class.getProtectionDomain().getCodeSource().getLocation().toString();
    assertTrue(where.contains("test-classes"), "GenericChainCompiler ships from " + where);
  }
}
