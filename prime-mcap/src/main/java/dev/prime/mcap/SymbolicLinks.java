package dev.prime.mcap;

import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;

/**
 * Follows symbolic links from a recording's path to the file a writer writes there, a merge
 * replaces there, and a lock holds (see {@link RecordingLock}), all in one way: through links to
 * links, whether the file is there yet or not; a loop of links, or a chain longer than the
 * system's own bound, is refused, naming the path and the fix, before anything is touched.
 */
final class SymbolicLinks {
  /** The most symbolic links followed from one path (Linux's own bound). */
  static final int MAX_LINKS = 40;

  private SymbolicLinks() {}

  /**
   * The file {@code path} leads to: {@code path} itself if it is no symbolic link, else the file
   * at the end of its links (each resolved against the folder of the link that names it),
   * whether that file exists yet or not.
   *
   * @param path the path given (to a writer, a merge, a lock)
   * @param action what the caller is about to do, for the refusal: "open an MCAP writer at"
   * @return the file the path leads to
   * @throws IOException if the path leads through more than {@value #MAX_LINKS} links (a loop of
   *     them), naming the path and what to do; or if a link cannot be read
   */
  static Path target(Path path, String action) throws IOException {
    return target(path, action, "make it a link to a file (or no link), or write to another path");
  }

  /**
   * As {@link #target(Path, String)}, for a caller whose fix for a loop of links is another's
   * (a reader's: to give the recording's first file).
   *
   * @param fix what to do about a loop of links, for the refusal
   */
  static Path target(Path path, String action, String fix) throws IOException {
    Path file = path;
    for (int links = 0; Files.isSymbolicLink(file); links++) {
      if (links == MAX_LINKS) {
        throw new IOException("cannot " + action + " " + path + ": it is a symbolic link that leads through more than "
            + MAX_LINKS + " links (a loop of them?), so it names no file; " + fix);
      }
      file = file.resolveSibling(Files.readSymbolicLink(file));
    }
    return file;
  }
}
