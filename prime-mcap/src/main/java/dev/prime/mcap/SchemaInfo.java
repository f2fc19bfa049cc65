package dev.prime.mcap;

import java.nio.charset.StandardCharsets;

/**
 * A Schema record of an MCAP file.
 *
 * @param id the schema id (not 0)
 * @param name its name (for prime-mcap files, the Java type with its type arguments)
 * @param encoding its encoding ({@code jsonschema} for prime-mcap files)
 * @param data the schema itself
 */
public record SchemaInfo(int id, String name, String encoding, byte[] data) {
  /** @return the schema data as UTF-8 text (a JSON Schema for {@code jsonschema}) */
  public String text() {
    return new String(data, StandardCharsets.UTF_8);
  }
}
