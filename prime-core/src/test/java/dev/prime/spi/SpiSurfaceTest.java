package dev.prime.spi;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import java.lang.reflect.Method;
import java.lang.reflect.Modifier;
import java.util.Arrays;
import java.util.Set;
import java.util.TreeSet;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;

/**
 * The media SPI stays small: what a media may override or call on {@link PrimeCore} is exactly
 * the protected methods listed here (everything else is the user API, public, or the core's own,
 * package-private); the core's chains, recorder and compiler are not public; the generic chain
 * compiler is a test fixture, not part of the shipped SPI.
 */
class SpiSurfaceTest {

  @Test
  void theCoreOffersMediaExactlyItsProtectedHooks() {
    Set<String> forMedia =
        Arrays.stream(PrimeCore.class.getDeclaredMethods())
            .filter(m -> Modifier.isProtected(m.getModifiers()))
            .map(Method::getName)
            .collect(Collectors.toCollection(TreeSet::new));
    assertEquals(
        new TreeSet<>(
            Set.of(
                "chainCompiler",
                "sourceCompiler",
                "sourcePart",
                "recordReader",
                "publishedTogether",
                "runGenericService",
                "hostOnCoreThreads",
                "unhostOnCoreThreads",
                "isHostedHere",
                "callerGaveUp",
                "isOwnThread",
                "startDetails",
                "onStart",
                "onClose",
                "ensureOpen",
                "ensureStartDidNotFail")),
        forMedia);
  }

  @Test
  void theCoresOwnMachineryIsNotPublic() throws ClassNotFoundException {
    for (String name :
        new String[] {
          "dev.prime.ModelChain",
          "dev.prime.ModelCompiler",
          "dev.prime.TopologyRecorder",
          "dev.prime.InProcessServices",
          "dev.prime.DeclarationLock",
          "dev.prime.IsolateBlock"
        }) {
      Class<?> type = Class.forName(name, false, PrimeCore.class.getClassLoader());
      assertFalse(Modifier.isPublic(type.getModifiers()), name + " is public");
    }
  }

  @Test
  void theGenericChainCompilerIsATestFixture() {
    String where =
        GenericChainCompiler.class.getProtectionDomain().getCodeSource().getLocation().toString();
    assertTrue(where.contains("test-classes"), "GenericChainCompiler ships from " + where);
  }
}
