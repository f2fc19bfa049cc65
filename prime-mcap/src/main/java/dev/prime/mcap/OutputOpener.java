package dev.prime.mcap;

import java.io.IOException;
import java.io.OutputStream;
import java.nio.file.Path;

/** Opens the output of one file (package-private: tests put a controllable output behind it). */
@FunctionalInterface
interface OutputOpener {
  /** The default: create or truncate the file. */
  OutputOpener FILES = java.nio.file.Files::newOutputStream;

  OutputStream open(Path path) throws IOException;
}
