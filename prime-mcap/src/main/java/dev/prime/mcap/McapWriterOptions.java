package dev.prime.mcap;

/**
 * How an {@link McapWriter} writes: chunk size, rotation by size, and the bounded queue between
 * the callers and the background writer thread. Immutable; each setter returns a copy.
 *
 * <pre>{@code
 * McapWriterOptions options = McapWriterOptions.defaults()
 *     .chunkSize(256 * 1024)
 *     .rotateAtSize(512L * 1024 * 1024)
 *     .queue(8192, 32L * 1024 * 1024);
 * }</pre>
 */
public final class McapWriterOptions {
  /** Default chunk size: 1 MiB of records per chunk. */
  public static final long DEFAULT_CHUNK_SIZE = 1 << 20;
  /** Default queue bound in messages. */
  public static final int DEFAULT_QUEUE_MESSAGES = 16_384;
  /** Default queue bound in bytes of encoded messages. */
  public static final long DEFAULT_QUEUE_BYTES = 64L << 20;

  private final long chunkSize;
  private final long rotateAtSize;
  private final int queueMessages;
  private final long queueBytes;
  private final String library;

  private McapWriterOptions(long chunkSize, long rotateAtSize, int queueMessages, long queueBytes, String library) {
    this.chunkSize = chunkSize;
    this.rotateAtSize = rotateAtSize;
    this.queueMessages = queueMessages;
    this.queueBytes = queueBytes;
    this.library = library;
  }

  /** @return 1 MiB chunks, no rotation, a background writer behind a queue of 16384 messages or 64 MiB */
  public static McapWriterOptions defaults() {
    return new McapWriterOptions(DEFAULT_CHUNK_SIZE, 0, DEFAULT_QUEUE_MESSAGES, DEFAULT_QUEUE_BYTES, "prime-mcap");
  }

  /**
   * @param bytes a chunk is written once its records reach this many bytes (1 writes every
   *     message in a chunk of its own)
   * @return a copy with this chunk size
   */
  public McapWriterOptions chunkSize(long bytes) {
    if (bytes < 1 || bytes > (1L << 30)) {
      throw new IllegalArgumentException("chunk size must be 1 byte to 1 GiB, was " + bytes);
    }
    return new McapWriterOptions(bytes, rotateAtSize, queueMessages, queueBytes, library);
  }

  /**
   * Rotation by size: once a file reaches this many bytes it is finished (summary, footer) and
   * the next messages go to the next file, named by {@link McapWriter#rotatedPath}. A message
   * is never split; a file ends a little past the limit (by up to a chunk and its summary).
   *
   * @param bytes the size to rotate at, or 0 never to rotate
   * @return a copy with this rotation size
   */
  public McapWriterOptions rotateAtSize(long bytes) {
    if (bytes < 0) {
      throw new IllegalArgumentException("rotation size must be 0 (never) or positive, was " + bytes);
    }
    return new McapWriterOptions(chunkSize, bytes, queueMessages, queueBytes, library);
  }

  /**
   * A background writer thread behind a queue bounded in messages and in bytes: a write that
   * finds the queue full is dropped and counted, never waits. A message larger than {@code bytes}
   * could never be queued: its write is refused with an {@link IllegalArgumentException}.
   *
   * @param messages at most this many messages wait to be written
   * @param bytes at most this many bytes of encoded messages wait to be written
   * @return a copy with this queue
   */
  public McapWriterOptions queue(int messages, long bytes) {
    if (messages < 1 || bytes < 1) {
      throw new IllegalArgumentException(
          "queue bounds must be positive, were " + messages + " messages and " + bytes
              + " bytes (use synchronous() for no queue)");
    }
    return new McapWriterOptions(chunkSize, rotateAtSize, messages, bytes, library);
  }

  /**
   * No queue and no thread: each write encodes and writes in the caller's thread (waiting for
   * the disk when a chunk is written) and never drops. For tools and tests, not for a
   * controller's hot path.
   *
   * @return a synchronous copy
   */
  public McapWriterOptions synchronous() {
    return new McapWriterOptions(chunkSize, rotateAtSize, 0, 0, library);
  }

  /**
   * @param name the Header's library field (the writer's name and version, for debugging)
   * @return a copy with this library name
   * @throws NullPointerException if {@code name} is null (give "" for no name)
   * @throws IllegalArgumentException if {@code name} has an unpaired surrogate (not Unicode text,
   *     which MCAP's UTF-8 strings cannot hold)
   */
  public McapWriterOptions library(String name) {
    if (name == null) {
      throw new NullPointerException(
          "library must not be null: give the writer's name and version, or \"\" for none");
    }
    McapWriter.requireUnicode(name, "library");
    return new McapWriterOptions(chunkSize, rotateAtSize, queueMessages, queueBytes, name);
  }

  /** @return the chunk size in bytes */
  public long chunkSize() {
    return chunkSize;
  }

  /** @return the rotation size in bytes, 0 for none */
  public long rotateAtSize() {
    return rotateAtSize;
  }

  /** @return the queue bound in messages, 0 when synchronous */
  public int queueMessages() {
    return queueMessages;
  }

  /** @return the queue bound in bytes, 0 when synchronous */
  public long queueBytes() {
    return queueBytes;
  }

  /** @return whether writes happen in the caller's thread */
  public boolean isSynchronous() {
    return queueMessages == 0;
  }

  /** @return the Header's library field */
  public String library() {
    return library;
  }
}
