package dev.prime.test;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import javax.xml.parsers.DocumentBuilderFactory;
import org.junit.jupiter.api.Test;
import org.w3c.dom.Element;
import org.w3c.dom.NodeList;

/**
 * The README's "Testing on every media": prime-test depends on prime-core and the JUnit Jupiter
 * API only, and the media are optional dependencies, so a Liberty-only project pulls no Redis.
 * Read from this module's pom (the parent adds no dependencies).
 */
class DependenciesTest {

  @Test
  void dependsOnTheCoreAndTheJupiterApiOnlyAndTheMediaAreOptional() throws Exception {
    List<String> required = new ArrayList<>();
    List<String> optional = new ArrayList<>();
    Element project =
        DocumentBuilderFactory.newInstance()
            .newDocumentBuilder()
            .parse(Path.of("pom.xml").toFile())
            .getDocumentElement();
    Element dependencies = child(project, "dependencies");
    NodeList all = dependencies.getElementsByTagName("dependency");
    for (int i = 0; i < all.getLength(); i++) {
      Element dependency = (Element) all.item(i);
      String scope = text(dependency, "scope");
      if ("test".equals(scope)) {
        continue;
      }
      String artifact = text(dependency, "groupId") + ":" + text(dependency, "artifactId");
      ("true".equals(text(dependency, "optional")) ? optional : required).add(artifact);
    }
    assertEquals(List.of("dev.prime:prime-core", "org.junit.jupiter:junit-jupiter-api"), required);
    assertEquals(
        List.of(
            "dev.prime:prime-liberty",
            "dev.prime:prime-radiant",
            "dev.prime:prime-optimus",
            "dev.prime:prime-redis-embedded"),
        optional);
  }

  private static Element child(Element parent, String name) {
    NodeList children = parent.getChildNodes();
    for (int i = 0; i < children.getLength(); i++) {
      if (children.item(i) instanceof Element e && e.getTagName().equals(name)) {
        return e;
      }
    }
    throw new AssertionError("no <" + name + "> in <" + parent.getTagName() + ">");
  }

  private static String text(Element parent, String name) {
    NodeList children = parent.getChildNodes();
    for (int i = 0; i < children.getLength(); i++) {
      if (children.item(i) instanceof Element e && e.getTagName().equals(name)) {
        return e.getTextContent().trim();
      }
    }
    return null;
  }
}
