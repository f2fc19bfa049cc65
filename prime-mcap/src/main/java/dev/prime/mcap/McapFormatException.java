package dev.prime.mcap;

import java.nio.file.Path;

/**
 * An MCAP file is malformed: not MCAP, truncated, or corrupt. The message names the file, the
 * byte offset and what is wrong.
 */
public final class McapFormatException extends RuntimeException {
  private static final long serialVersionUID = 1L;

  private final transient Path path;
  /** The byte offset where the problem is, or -1. */
  private final long offset;

  /**
   * @param path the file
   * @param offset the byte offset where the problem is, or -1
   * @param problem what is wrong and, where it helps, what to do
   */
  public McapFormatException(Path path, long offset, String problem) {
    super(path + (offset >= 0 ? " at byte " + offset : "") + ": " + problem);
    this.path = path;
    this.offset = offset;
  }

  /** @return the file */
  public Path path() {
    return path;
  }

  /** @return the byte offset where the problem is, or -1 */
  public long offset() {
    return offset;
  }
}
