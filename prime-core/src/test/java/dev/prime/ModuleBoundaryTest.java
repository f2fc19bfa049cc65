package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.lang.module.ModuleDescriptor;
import java.util.Set;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;

/**
 * prime-core is the module {@code dev.prime}, exporting its public packages to everyone and its
 * internals to the Optimus media only.
 */
class ModuleBoundaryTest {

  @Test
  void onlyThePublicPackagesAreExported() {
    Module core = PrimeCore.class.getModule();
    assertTrue(core.isNamed(), "the tests run prime-core as a named module");
    assertEquals("dev.prime", core.getName());
    assertEquals(
        Set.of("dev.prime", "dev.prime.spi", "dev.prime.topology"),
        core.getDescriptor().exports().stream()
            .filter(e -> !e.isQualified())
            .map(ModuleDescriptor.Exports::source)
            .collect(Collectors.toSet()));
    assertEquals(
        Set.of("dev.prime.internal -> [dev.prime.optimus]"),
        core.getDescriptor().exports().stream()
            .filter(ModuleDescriptor.Exports::isQualified)
            .map(e -> e.source() + " -> " + e.targets())
            .collect(Collectors.toSet()),
        "the internals are exported to Optimus alone");
    assertTrue(core.getPackages().contains("dev.prime.internal"));
    assertFalse(core.getDescriptor().isOpen());
  }
}
