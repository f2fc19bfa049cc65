package dev.prime.mcap;

import java.io.IOException;
import java.nio.channels.FileChannel;
import java.nio.file.Path;
import java.util.Locale;

/**
 * Forces what a writer or a merge finished to the storage device, so that a power cut after it
 * leaves it as it was finished: the file's bytes and size (forced by the file's own channel, see
 * {@link dev.prime.mcap.internal.McapFileWriter#finish()}), and the folder's entry for it (a file
 * made, or moved into place, is found after a power cut only once its folder is forced).
 */
final class Durability {
  /**
   * Windows opens no folder as a channel (the JDK's CreateFile lacks the flag that folders need
   * and fails with AccessDeniedException); NTFS journals the entries of its folders itself.
   */
  private static final boolean FOLDERS_OPEN =
      !System.getProperty("os.name", "").toLowerCase(Locale.ROOT).startsWith("windows");

  private Durability() {}

  /**
   * Forces the folder of {@code file}, so that the file's entry there (made or replaced) survives
   * a power cut: for a symbolic link, the folder of the file it leads to, whose entry writing
   * through the link made, not the link's own, which the write left as it was. Nothing is done on a platform that opens no folder, nor on a file system that
   * makes no file channels ({@link UnsupportedOperationException}, as {@link
   * java.nio.file.spi.FileSystemProvider#newFileChannel} documents).
   *
   * @param file a file just finished, or moved into place
   * @param opener opens the folder
   * @throws IOException if the folder cannot be opened (the message says so and what to do) or
   *     forced
   */
  static void forceFolderOf(Path file, OutputOpener opener) throws IOException {
    Path written = fileAt(file);
    Path folder = written.getParent();
    if (folder == null || !FOLDERS_OPEN) {
      return;
    }
    FileChannel channel;
    try {
      channel = opener.openFolder(folder);
    } catch (UnsupportedOperationException e) {
      return; // a file system that makes no channels: nothing to force through
    } catch (IOException e) {
      // the JDK's own message is the folder's path alone (an AccessDeniedException, say)
      throw new IOException("cannot open the folder " + folder + " to force its entry for " + written.getFileName()
          + " to the storage device, so that it survives a power cut (the file itself is finished and forced): "
          + e + "; give this user read access to the folder, or write to a folder it can read", e);
    }
    try (FileChannel open = channel) {
      open.force(true);
    } catch (IOException e) {
      throw new IOException("cannot force the folder " + folder + " to the storage device, so that its entry for "
          + written.getFileName() + " survives a power cut: " + e, e);
    }
  }

  /** The file at {@code path}, where its links lead; the path itself if nothing is there to follow. */
  private static Path fileAt(Path path) {
    try {
      return path.toRealPath();
    } catch (IOException | SecurityException e) {
      return path.toAbsolutePath(); // nothing there to follow: the file it names
    }
  }
}
