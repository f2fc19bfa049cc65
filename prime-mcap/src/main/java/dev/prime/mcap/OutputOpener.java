package dev.prime.mcap;

import java.io.IOException;
import java.nio.channels.FileChannel;
import java.nio.file.Path;
import java.nio.file.StandardOpenOption;

/**
 * Opens the files a writer or a merge writes, and the folders it forces (package-private: tests
 * put a channel they control or watch behind it).
 */
@FunctionalInterface
interface OutputOpener {
  /** The default: create or truncate the file. */
  OutputOpener FILES =
      path -> FileChannel.open(path, StandardOpenOption.CREATE, StandardOpenOption.WRITE,
          StandardOpenOption.TRUNCATE_EXISTING);

  /**
   * Opens a file to write it from its start.
   *
   * @param path the file: created, or truncated
   * @return a channel open for writing
   * @throws IOException if the file cannot be created or truncated
   */
  FileChannel open(Path path) throws IOException;

  /**
   * Opens a folder to force its entries to the storage device (see {@link Durability}).
   *
   * @param folder the folder
   * @return a channel open for reading
   * @throws IOException if the folder cannot be opened
   */
  default FileChannel openFolder(Path folder) throws IOException {
    return FileChannel.open(folder, StandardOpenOption.READ);
  }
}
