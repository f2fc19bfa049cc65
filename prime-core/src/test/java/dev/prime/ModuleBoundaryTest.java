package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.lang.module.ModuleDescriptor;
import java.util.Set;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;

/** prime-core is the module {@code dev.prime}, exporting its public packages and no other. */
class ModuleBoundaryTest {

  @Test
  void onlyThePublicPackagesAreExported() {
    Module core = PrimeCore.class.getModule();
    assertTrue(core.isNamed(), "the tests run prime-core as a named module");
    assertEquals("dev.prime", core.getName());
    assertEquals(
        Set.of("dev.prime", "dev.prime.spi", "dev.prime.topology"),
        core.getDescriptor().exports().stream()
            .map(ModuleDescriptor.Exports::source)
            .collect(Collectors.toSet()));
    assertTrue(core.getPackages().contains("dev.prime.internal"));
    assertFalse(core.getDescriptor().isOpen());
  }
}
