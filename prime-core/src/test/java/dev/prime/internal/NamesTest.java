package dev.prime.internal;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.HashSet;
import java.util.Set;
import org.junit.jupiter.api.Test;

class NamesTest {

  @Test
  void claimRefusesDuplicatesAndInvalidNames() {
    Names names = new Names();
    assertEquals("a", names.claim("a"));
    IllegalArgumentException dup = assertThrows(IllegalArgumentException.class, () -> names.claim("a"));
    assertTrue(dup.getMessage().contains("'a'"), dup.getMessage());
    assertThrows(NullPointerException.class, () -> names.claim(null));
    assertThrows(IllegalArgumentException.class, () -> names.claim(""));
    assertThrows(IllegalArgumentException.class, () -> names.claim("a b"));
    assertThrows(IllegalArgumentException.class, () -> names.claim("a\nb"));
    assertThrows(IllegalArgumentException.class, () -> names.claim("a{b}"));
    assertThrows(IllegalArgumentException.class, () -> names.claim("x".repeat(201)));
    assertEquals("x".repeat(200), names.claim("x".repeat(200)));
  }

  @Test
  void freshNamesSkipClaimedOnes() {
    Names names = new Names();
    names.claim("chain-1");
    assertEquals("chain-2", names.fresh("chain"));
    assertEquals("chain-3", names.fresh("chain"));
    assertEquals("source-1", names.fresh("source"));
  }

  @Test
  void derivedNamesAreUniqueAndFallBackWhenTooLongOrInvalid() {
    Names names = new Names();
    assertEquals("a>b", names.derived("a>b", "link"));
    assertEquals("a>b#2", names.derived("a>b", "link"));
    assertEquals("a>b#3", names.derived("a>b", "link"));
    assertEquals("link-1", names.derived("y".repeat(121), "link"));
    assertEquals("link-2", names.derived("has space", "link"));
    Set<String> all = new HashSet<>();
    for (int i = 0; i < 100; i++) {
      assertTrue(all.add(names.derived("same", "k")));
    }
    assertNotEquals(names.fresh("k"), names.fresh("k"));
  }
}
