package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotEquals;

import dev.prime.Block;
import java.lang.module.ModuleDescriptor;
import java.util.Set;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;

/**
 * prime-radiant is the module {@code dev.prime.radiant}, exporting only its API; the fused
 * classes, defined in loaders of their own outside the module, still reach its internals.
 */
class RadiantModuleTest {

  @Test
  void onlyTheApiIsExportedAndFusedClassesStillRun() {
    Module radiant = RadiantCore.class.getModule();
    assertEquals("dev.prime.radiant", radiant.getName());
    assertEquals(
        Set.of("dev.prime.radiant"),
        radiant.getDescriptor().exports().stream()
            .map(ModuleDescriptor.Exports::source)
            .collect(Collectors.toSet()));
    assertFalse(radiant.isExported("dev.prime.radiant.internal"));
    try (RadiantCore core = new RadiantCore()) {
      Block<Integer, Integer> fused =
          core.chain((Integer x) -> x + 1).then((Integer x) -> x * 2).toBlock();
      assertNotEquals(radiant, fused.getClass().getModule(), "fused outside the module");
      assertEquals(8, fused.process(3));
    }
  }
}
