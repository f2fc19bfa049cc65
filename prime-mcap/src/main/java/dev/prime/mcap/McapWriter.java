package dev.prime.mcap;

import dev.prime.mcap.internal.McapFileWriter;
import java.io.Closeable;
import java.io.IOException;
import java.io.InterruptedIOException;
import java.io.UncheckedIOException;
import java.nio.channels.FileChannel;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.LinkOption;
import java.nio.file.Path;
import java.nio.file.StandardOpenOption;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.SortedMap;
import java.util.TreeMap;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.LinkedBlockingQueue;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicLong;
import java.util.concurrent.atomic.LongAdder;

/**
 * Writes MCAP files (mcap.dev): one channel per topic, JSON messages, a JSON Schema per value
 * type, uncompressed chunks with message indexes, and a summary section (schemas, channels,
 * statistics, chunk indexes, metadata indexes, summary offsets) so readers can seek.
 *
 * <pre>{@code
 * try (McapWriter writer = McapWriter.open(Path.of("run.mcap"))) {
 *   McapChannel<Pose> poses = writer.channel("odometry", Pose.class);
 *   poses.write(logTime, publishTime, sequence, pose);
 * }
 * }</pre>
 *
 * <h2>Design note: threading and memory</h2>
 *
 * The caller is a robot controller that must never wait for a disk. So, by default, a write
 * encodes the value to JSON in the caller's thread (a snapshot: mutable values may change right
 * after) and offers the bytes to a queue bounded both in messages and in bytes; one background
 * thread (a daemon, one per writer) takes them, batches them into chunks and writes the files.
 * A write that finds the queue full does not wait: the message is dropped, counted in
 * {@link #droppedCount()} and per channel, and the loss is reported in the file itself (a
 * {@code prime.mcap} Metadata record per file: {@code dropped_messages} and
 * {@code dropped.<topic>} counts, and {@code unwritable_messages}, the values an {@link
 * McapRecorder} could not write at all, see {@link McapRecorder#unwritableCount()}; 0 when the
 * writer is used directly). A message larger than the queue's byte bound could never be
 * queued, not even on an empty queue: its write is refused with an {@link
 * IllegalArgumentException} naming its size and the bound, and nothing is dropped. If the disk
 * fails, the writer thread stops writing, the messages after it count as dropped, and {@link
 * #close()} throws the failure, naming the file and saying that it is left unfinished (without
 * its summary and footer: {@link McapReader#openUnfinished} reads the records written before the
 * failure).
 *
 * <p>Memory is bounded by the queue's byte bound, plus the open chunk (about the chunk size),
 * plus a chunk index (about 70 bytes, and 10 per channel in the chunk) per chunk of the current
 * file: rotation by size bounds that last term and the disk used per file.
 *
 * <p>Channels are defined from any thread; the writer thread adds a channel's Schema and
 * Channel records to a file before its first message there, and every file's summary lists
 * every channel defined so far (with zero messages if none came), so each rotated file stands
 * alone. {@link #close()} waits for the queue to drain, then writes the summary and footer.
 * With {@link McapWriterOptions#synchronous()} there is no queue and no thread: writes happen
 * in the caller's thread under a lock and never drop.
 *
 * <h2>Rotation naming</h2>
 *
 * With {@link McapWriterOptions#rotateAtSize(long)}, the first file is the path given; the
 * n-th next one inserts {@code -NNNN} (n, at least 4 digits) before the last dot of the file
 * name: {@code run.mcap}, {@code run-0001.mcap}, {@code run-0002.mcap}, ... (no dot: the suffix
 * goes at the end). At a symbolic link ({@code latest.mcap} to {@code runs/run.mcap}) they are
 * named after the file the link leads to, beside it ({@code runs/run-0001.mcap}, ...; {@link
 * #files()} gives the first file as the path given): the recording's files lie together, it is the
 * same recording read through either name ({@link McapReader#recordingFiles}), and a link moved on
 * to the next run's file leaves the earlier run whole. A file is finished once it reaches the size, and the next one is started by
 * the next message (or at close, only to hold messages dropped or Metadata records added since),
 * so a recording does not end with an empty file. Existing files of those names are overwritten.
 * A recording's rotated files are thus contiguous, from {@code -0001} on: a gap of more than
 * two names ends it (a gap of one or two is taken for files moved or deleted by hand), so that a file further on whose name only looks like a rotated file's (a user's
 * date-named {@code run-2026.mcap} beside {@code run.mcap}) is no file of it, never deleted by a
 * writer or merge opened at {@code run.mcap} nor listed by {@link McapReader#recordingFiles}.
 * See {@link #rotatedPath}.
 *
 * <h2>Durability</h2>
 *
 * A file is forced to the storage device (fsync: its bytes, its size, and its folder's entry for
 * it) when it is finished: each rotated file as it reaches the rotation size (in the writer
 * thread; with {@link McapWriterOptions#synchronous()}, in the thread whose write finished it),
 * and the last one in {@link #close()}, before it returns. So a power cut after {@code close()}
 * returned leaves the whole recording as it was written. A write is a hot path and never forces:
 * messages are handed to the operating system as their chunk closes, and a power cut loses what
 * it had not yet stored, and leaves the file being written unfinished ({@link
 * McapReader#openUnfinished} reads the complete chunks that reached the disk). A device or a pipe
 * ({@code /dev/null}) is not forced.
 *
 * <h2>One writer per path</h2>
 *
 * A writer holds its recording's path from {@link #open} until its last file is finished in
 * {@link #close()}: a second writer (or {@link McapRecorder}) opened at the same path, in this
 * JVM or in another process, is refused with an {@link IOException} naming the path and the
 * holder (pid, host, thread), before anything is truncated or deleted. So is one whose files
 * would overlap with the holder's: a writer, recorder or merge at {@code run-0001.mcap} while a
 * writer at {@code run.mcap} holds its recording (it rotates into that name, truncating it), and
 * a writer at {@code run.mcap} while one at {@code run-0001.mcap} is writing (it would delete
 * that file as an earlier recording's, then rotate into it), or a merge ({@link McapMerge}) into
 * {@code run.mcap} then ({@link McapReader#recordingFiles} would list the file being written as
 * the second of the merge's recording). Writers at {@code run-0001.mcap} and
 * {@code run-0002.mcap} do not overlap, and may write at once. A writer opened at a symbolic
 * link holds the file it links to as well: a writer at {@code latest.mcap}, a link to {@code
 * run.mcap}, is refused while {@code run.mcap} is written, and the other way round. A path that
 * is a loop of symbolic links (or leads through more than 40) names no file: a writer (or merge)
 * there is refused, naming the path and the fix, before anything is made or deleted. Across processes this is
 * an advisory lock on {@code <path>.lock} beside the file, deleted at close; the operating system
 * releases it when its process dies, so the lock file a killed process leaves does not stop the
 * next writer. A device or a pipe ({@code /dev/null}) is not held.
 *
 * <p>Only {@link #close()} gives the path up before the process ends. A writer that is never
 * closed holds it, and its lock file, until its JVM exits, and its last file stays unfinished
 * ({@link McapReader#openUnfinished} reads it): the writer thread, which waits for the next
 * message, keeps the writer reachable, so garbage collection never frees it, and nothing
 * releases the path on its behalf (that would let a new writer truncate a file the first may
 * still write). A synchronous writer has no thread: once one is dropped unclosed and garbage
 * collected, the operating system may release its lock file's lock, so that another process can
 * take the path, while this JVM still refuses it until it exits. Close every writer, in a {@code
 * try}-with-resources or a {@code finally}.
 */
public final class McapWriter implements Closeable {
  /** The message encoding of every channel this writer makes. */
  public static final String MESSAGE_ENCODING = "json";
  /** The schema encoding of every schema this writer makes. */
  public static final String SCHEMA_ENCODING = "jsonschema";
  /** The name of the Metadata record that reports losses, one per file. */
  public static final String LOSS_METADATA = "prime.mcap";

  /**
   * The key of the loss record ({@value #LOSS_METADATA}) that counts the values a recorder ({@link
   * McapRecorder}) could not write while the file was being written; 0 for a writer used directly.
   */
  static final String UNWRITABLE_MESSAGES = "unwritable_messages";

  /** The most channels a file holds: channel ids are 16 bits, and 0 is none. */
  static final int MAX_CHANNELS = 0xFFFF;

  private final Path firstPath;
  /**
   * What the rotated files are named after: {@link #firstPath}, or, if that is a symbolic link,
   * the file it leads to, so that they lie beside the recording's first file and are its files
   * read through either name ({@link McapReader#recordingFiles}).
   */
  private final Path rotationBase;
  private final McapWriterOptions options;
  private final OutputOpener opener;
  /**
   * Whether a file left unfinished by a failure is removed (or, if it was there before, emptied)
   * rather than kept for {@link McapReader#openUnfinished}: for a snapshot written at once
   * ({@link RecordingMcap#write}), whose caller still has what it wrote, not for a recording
   * streamed over a run, whose complete chunks are worth reading.
   */
  private final boolean discardUnfinished;
  /** This writer's hold on the recording's path; released once its last file is finished. */
  private final RecordingLock lock;

  private final Object definitions = new Object();
  private final Map<String, McapChannel<?>> channelsByTopic = new LinkedHashMap<>();
  private final Map<ValueType<?>, Integer> schemaIds = new HashMap<>();
  private final Map<Integer, McapChannel<?>> channelsById = new ConcurrentHashMap<>();
  private final Map<Integer, Integer> schemaOfChannel = new ConcurrentHashMap<>();
  private final Map<Integer, Map<String, String>> channelMetadata = new ConcurrentHashMap<>();
  private final List<Map.Entry<String, Map<String, String>>> metadata = new CopyOnWriteArrayList<>();

  private final BlockingQueue<Entry> queue;
  private final AtomicLong queuedBytes = new AtomicLong();
  private final LongAdder dropped = new LongAdder();
  /** Values an {@link McapRecorder} could not write (see {@link #countUnwritable()}). */
  private final LongAdder unwritable = new LongAdder();
  private final AtomicInteger inFlight = new AtomicInteger();
  private volatile boolean closed;
  private final Thread thread;
  private final Object syncLock = new Object();
  private final CountDownLatch closeFinished = new CountDownLatch(1);

  // Owned by the writer thread (or, when synchronous, by whoever holds syncLock).
  /** The file being written; null between a rotation and the next message, which starts the next file. */
  private McapFileWriter file;
  /** Whether {@link #file} is a regular file (forced when finished), not a device or a pipe. */
  private boolean fileIsRegular;
  /** Whether a file was at {@link #file}'s path (or where its link leads) before it was opened (and truncated). */
  private boolean fileExisted;
  /** The file {@link #file} writes: its path, or, if that is a symbolic link, the file it leads to. */
  private Path fileTarget;
  /** What became of the file being written when writing failed; set as the last file is finished. */
  private volatile String failedFileFate;
  private int fileIndex;
  private long droppedAtFileStart;
  private long unwritableAtFileStart;
  private int metadataAtFileStart;
  private final Map<Integer, Long> channelDroppedAtFileStart = new HashMap<>();
  private volatile IOException failure;
  private final List<Path> files = new CopyOnWriteArrayList<>();

  private static final class Entry {
    final McapChannel<?> channel;
    final long sequence;
    final long logTime;
    final long publishTime;
    final byte[] data;

    Entry(McapChannel<?> channel, long sequence, long logTime, long publishTime, byte[] data) {
      this.channel = channel;
      this.sequence = sequence;
      this.logTime = logTime;
      this.publishTime = publishTime;
      this.data = data;
    }
  }

  private static final Entry CLOSE = new Entry(null, 0, 0, 0, new byte[0]);

  /** The largest message bound given an array queue (its array: 4 to 8 MiB). */
  private static final int ARRAY_QUEUE_LIMIT = 1 << 20;

  private McapWriter(Path path, McapWriterOptions options, OutputOpener opener, boolean discardUnfinished)
      throws IOException {
    this.firstPath = path;
    this.options = options;
    this.opener = opener;
    this.discardUnfinished = discardUnfinished;
    this.rotationBase = SymbolicLinks.target(path, "open an MCAP writer at");
    // before anything is truncated or deleted: those are the files of a writer that holds the path
    this.lock = RecordingLock.acquire(path, "open an MCAP writer at", true);
    try {
      // the earlier recording's rotated files go before its first file is overwritten: an open
      // that fails on the way leaves that first file and the rotated files it has not reached
      deleteEarlierRotatedFiles(rotationBase);
      openFile(path);
    } catch (IOException | RuntimeException | Error e) {
      releaseLock(e);
      throw e;
    }
    if (options.isSynchronous()) {
      queue = null;
      thread = null;
    } else {
      // An array queue allocates its whole bound up front: a bound of more messages than
      // ARRAY_QUEUE_LIMIT (queue() takes up to Integer.MAX_VALUE) gets a linked queue, which
      // allocates per message queued, so that memory stays bounded by the byte bound.
      queue =
          options.queueMessages() <= ARRAY_QUEUE_LIMIT
              ? new ArrayBlockingQueue<>(options.queueMessages())
              : new LinkedBlockingQueue<>(options.queueMessages());
      thread = new Thread(this::drain, "prime-mcap-writer " + path.getFileName());
      thread.setDaemon(true);
      thread.start();
    }
  }

  /**
   * Deletes the rotated files of an earlier recording at {@code path}: not to be read as this
   * one's. Refuses, having deleted nothing, if one of them is no file (a folder with its name:
   * it could not be deleted); else deletes them from the last one back, so that one whose
   * deletion fails leaves the earlier recording's files before it in place, a recording that
   * {@link McapReader#recordingFiles} lists without a gap.
   */
  static void deleteEarlierRotatedFiles(Path path) throws IOException {
    List<Path> earlier = new ArrayList<>(rotatedFilesIn(path).values());
    if (earlier.isEmpty()) {
      return;
    }
    if (Files.isRegularFile(path) || Files.isDirectory(path)) {
      // a first file that cannot be written (a folder, or not this user's to write) fails the
      // open here, as its own open would, before anything is deleted; not a pipe, whose open
      // would wait for a reader
      FileChannel.open(path, StandardOpenOption.WRITE).close();
    }
    for (Path rotated : earlier) {
      if (Files.isDirectory(rotated, LinkOption.NOFOLLOW_LINKS)) {
        throw new IOException(cannotDelete(rotated, path, "it is a folder, not a file"));
      }
    }
    for (int i = earlier.size() - 1; i >= 0; i--) {
      Path rotated = earlier.get(i);
      try {
        Files.deleteIfExists(rotated);
      } catch (IOException e) {
        throw new IOException(cannotDelete(rotated, path, e.toString()), e);
      }
    }
  }

  private static String cannotDelete(Path rotated, Path path, String why) {
    return "cannot delete " + rotated + ", a rotated file of an earlier recording at " + path
        + " (a new writer or merge there replaces that recording): " + why
        + "; remove or move it, or write the recording to another path (the earlier recording's files"
        + " before it, from " + path + " on, are left as they were)";
  }

  /**
   * Opens a writer with {@link McapWriterOptions#defaults()}.
   *
   * @param path the (first) file; created or replaced, and the rotated files of an earlier
   *     recording at this path deleted (see {@link #open(Path, McapWriterOptions)}, which says in
   *     what order, and what a failed open leaves)
   * @return the writer
   * @throws IOException if the file cannot be created, or an earlier recording's file deleted, or
   *     its Header written, or another writer (in this JVM or another process) is writing the
   *     recording at the path: the message names the path and that writer (see "One writer per
   *     path" in the class description)
   */
  public static McapWriter open(Path path) throws IOException {
    return open(path, McapWriterOptions.defaults());
  }

  /**
   * Opens a writer. Opening replaces the recording at {@code path}, in this order:
   *
   * <ol>
   *   <li>what can be checked without touching it: the options (where they are given), that no
   *       writer holds the path (see "One writer per path" in the class description), and, if
   *       an earlier recording there has rotated files, that its first file can be opened to
   *       write and none of those files is a folder. A failure here leaves every file as it was;
   *   <li>the rotated files of an earlier recording at this path ({@link #rotatedPath}{@code
   *       (path, n)}, n from 1 up to a gap of more than two names, which ends a recording (a
   *       smaller one is taken for files moved or deleted by hand): a file further on, such as a user's date-named {@code run-2026.mcap}, is no file of it and
   *       is left) are deleted, so that {@link McapReader#recordingFiles} lists this
   *       recording's files only, from the last one back: an open that fails on one leaves the
   *       earlier recording's first file and the rotated files before that one. At a symbolic
   *       link these are the files named after the file it leads to ({@code runs/run-0001.mcap}...
   *       for {@code latest.mcap} to {@code runs/run.mcap}, the names this writer's rotations
   *       take); files named after the link ({@code latest-0001.mcap}) are no file of the
   *       recording, and are left;
   *   <li>the first file is opened: created, or truncated to nothing (a file that cannot be opened
   *       to write, such as one without write permission, fails here as it was, untruncated);
   *   <li>its magic and Header are written. An I/O error here (a full disk, a failing device),
   *       which no check can foresee, fails the open: a file the open created is removed, so the
   *       path is as it was; a file that was there is left truncated (empty, or with part of the
   *       Header; not an MCAP file), what it held gone. The exception says which. At a symbolic
   *       link, the file is the one the link leads to: a link to a file not there yet has the open
   *       create that file, which such a failure removes, the link left as it was.
   * </ol>
   *
   * To keep an earlier recording, open the writer at another path (or move the recording first).
   *
   * @param path the (first) file; created, or truncated and overwritten (see above)
   * @param options chunk size, rotation, queue
   * @return the writer
   * @throws IOException if the file cannot be created, or an earlier recording's file deleted, or
   *     its Header written, or another writer (in this JVM or another process) is writing the
   *     recording at the path: the message names the path and that writer (see "One writer per
   *     path" in the class description)
   */
  public static McapWriter open(Path path, McapWriterOptions options) throws IOException {
    return open(path, options, OutputOpener.FILES);
  }

  static McapWriter open(Path path, McapWriterOptions options, OutputOpener opener) throws IOException {
    return open(path, options, opener, false);
  }

  /**
   * Opens a writer that, if writing fails after its Header, removes the file it was writing (if
   * it created it) or leaves it empty (if it truncated an earlier one), rather than leave an
   * unfinished file that a reader could take for a recording; one file only (no rotation).
   */
  static McapWriter open(Path path, McapWriterOptions options, OutputOpener opener, boolean discardUnfinished)
      throws IOException {
    Objects.requireNonNull(path, "path");
    Objects.requireNonNull(options, "options");
    return new McapWriter(path, options, opener, discardUnfinished);
  }

  /**
   * The name of the {@code index}-th file of a rotated recording.
   *
   * @param first the path given to {@link #open}; if that is a symbolic link, the file it leads
   *     to, after which a writer opened at the link names its rotated files
   * @param index 0 for the first file, n for the n-th rotation
   * @return {@code first} for 0, else {@code first} with {@code -NNNN} before its extension
   */
  public static Path rotatedPath(Path first, int index) {
    Objects.requireNonNull(first, "first must not be null: give the path the writer was opened with");
    if (index < 0) {
      throw new IllegalArgumentException("rotation index must not be negative, was " + index);
    }
    if (index == 0) {
      return first;
    }
    String name = first.getFileName().toString();
    int dot = extensionAt(name);
    return first.resolveSibling(
        String.format("%s-%04d%s", name.substring(0, dot), index, name.substring(dot)));
  }

  /**
   * The most names a gap in a recording's rotated files spans and is still taken for files of it
   * moved or deleted by hand (which {@link McapReader#recordingFiles} refuses over, and a new
   * writer or merge deletes); a longer gap ends the recording.
   */
  static final int GAP_BRIDGED = 2;

  /**
   * The rotated files of a recording at {@code first}, by index (1 and up), whoever wrote them:
   * this writer, or an earlier one at the same path. They are contiguous: {@link #rotatedPath}
   * {@code (first, 1)}, {@code (first, 2)}, ... (a writer rotates into them in order, and deletes
   * an earlier recording's from the last one back, leaving a prefix), but for a gap of at most
   * {@value #GAP_BRIDGED} names, a file or two moved or deleted by hand. A longer gap ends the
   * recording: a file further on whose name only looks like a rotated file's ({@code
   * run-2026.mcap}, a user's date-named file, beside {@code run.mcap}) is no file of it, so
   * nothing here ever lists or deletes it.
   */
  static SortedMap<Integer, Path> rotatedFilesIn(Path first) {
    SortedMap<Integer, Path> found = new TreeMap<>();
    int missing = 0;
    for (int index = 1; index < Integer.MAX_VALUE && missing <= GAP_BRIDGED; index++) {
      Path rotated = rotatedPath(first, index);
      // not following links: a link left with a rotated file's name is one too
      if (Files.exists(rotated, LinkOption.NOFOLLOW_LINKS)) {
        found.put(index, rotated);
        missing = 0;
      } else {
        missing++;
      }
    }
    return found;
  }

  /**
   * The rotation index {@code file} has as a file of {@code first}'s recording, as {@link
   * #rotatedPath} names them (1 and up); -1 if its name is not one of them.
   */
  static int rotationIndex(Path first, Path file) {
    String name = first.getFileName().toString();
    String stem = name.substring(0, extensionAt(name)) + "-";
    String extension = name.substring(extensionAt(name));
    String other = file.getFileName().toString();
    if (!other.startsWith(stem)
        || !other.endsWith(extension)
        || other.length() < stem.length() + 4 + extension.length()) {
      return -1;
    }
    String digits = other.substring(stem.length(), other.length() - extension.length());
    if (digits.length() > 9 || !digits.chars().allMatch(c -> c >= '0' && c <= '9')) {
      return -1;
    }
    int index = Integer.parseInt(digits);
    return index > 0 && file.getFileName().equals(rotatedPath(first, index).getFileName()) ? index : -1;
  }

  /**
   * The first file of the recording that {@code file} is a rotated file of, by its name ({@code
   * run.mcap} for {@code run-0001.mcap}); null if its name is no rotated file's.
   */
  static Path recordingOf(Path file) {
    Path fileName = file.getFileName();
    if (fileName == null) {
      return null;
    }
    String name = fileName.toString();
    int dot = extensionAt(name);
    int dash = name.lastIndexOf('-', dot - 1);
    if (dash <= 0) {
      return null;
    }
    Path first = file.resolveSibling(name.substring(0, dash) + name.substring(dot));
    return rotationIndex(first, file) > 0 ? first : null;
  }

  /** Where a file name's extension starts: at its last dot, if not the first character; else its end. */
  private static int extensionAt(String name) {
    int dot = name.lastIndexOf('.');
    return dot > 0 ? dot : name.length();
  }

  /**
   * Defines a channel for a non-generic type.
   *
   * @param topic the topic (one channel per topic)
   * @param type the values' class
   * @param <T> the values' type
   * @return the channel; the same one if the topic was defined before with the same type
   * @throws IllegalArgumentException if the type is not supported, the topic has another type, or
   *     it has an unpaired surrogate (not Unicode text, which MCAP's UTF-8 strings cannot hold)
   */
  public <T> McapChannel<T> channel(String topic, Class<T> type) {
    return channel(topic, ValueType.of(type), Map.of());
  }

  /**
   * Defines a channel.
   *
   * @param topic the topic (one channel per topic)
   * @param type the values' type, e.g. {@code new ValueType<Tuple2<Double, String>>() {}}
   * @param <T> the values' type
   * @return the channel; the same one if the topic was defined before with the same type
   * @throws IllegalArgumentException if the topic has another type, or an unpaired surrogate
   */
  public <T> McapChannel<T> channel(String topic, ValueType<T> type) {
    return channel(topic, type, Map.of());
  }

  /**
   * Defines a channel with metadata (stored in its Channel record).
   *
   * @param topic the topic (one channel per topic)
   * @param type the values' type
   * @param metadata key/value pairs for the Channel record
   * @param <T> the values' type
   * @return the channel; the same one if the topic was defined before with the same type
   * @throws IllegalArgumentException if the topic has another type or 65535 channels exist, or
   *     the topic or a metadata key or value has an unpaired surrogate (not Unicode text, which
   *     MCAP's UTF-8 strings cannot hold)
   * @throws NullPointerException for a null metadata key or value
   */
  public <T> McapChannel<T> channel(String topic, ValueType<T> type, Map<String, String> metadata) {
    Objects.requireNonNull(topic, "topic");
    Objects.requireNonNull(type, "type");
    Objects.requireNonNull(metadata, "metadata must not be null: give Map.of() for none");
    checkChannel(topic, metadata);
    synchronized (definitions) {
      if (closed) {
        throw new IllegalStateException("MCAP writer for " + firstPath + " is closed");
      }
      McapChannel<?> existing = channelsByTopic.get(topic);
      if (existing != null) {
        if (!existing.type().equals(type)) {
          throw new IllegalArgumentException(
              "topic '" + topic + "' already records " + existing.type().name() + ", not "
                  + type.name() + ": one topic, one type");
        }
        @SuppressWarnings("unchecked")
        McapChannel<T> same = (McapChannel<T>) existing;
        return same;
      }
      if (channelsByTopic.size() >= MAX_CHANNELS) {
        throw new IllegalArgumentException(
            "an MCAP file holds at most " + MAX_CHANNELS + " channels (channel ids are 16 bits): topic '" + topic
                + "' would be one more; write the other topics to another file");
      }
      Integer schemaId = schemaIds.get(type);
      if (schemaId == null) {
        schemaId = schemaIds.size() + 1;
        schemaIds.put(type, schemaId);
      }
      McapChannel<T> channel = new McapChannel<>(this, channelsByTopic.size() + 1, topic, type);
      channelMetadata.put(channel.id(), new TreeMap<>(metadata));
      schemaOfChannel.put(channel.id(), schemaId);
      channelsById.put(channel.id(), channel);
      channelsByTopic.put(topic, channel);
      return channel;
    }
  }

  /**
   * Refuses a channel's topic or metadata that {@link #channel(String, ValueType, Map)} would
   * refuse, as it would; for callers that must refuse it before a writer opens (and replaces the
   * recording at its path).
   */
  static void checkChannel(String topic, Map<String, String> metadata) {
    if (topic.isEmpty()) {
      throw new IllegalArgumentException("an MCAP topic must not be empty");
    }
    requireUnicode(topic, "topic");
    metadata.forEach((key, value) -> {
      requireUnicode(key, "metadata key of topic '" + topic + "'");
      requireUnicode(value, "metadata value of '" + key + "' on topic '" + topic + "'");
    });
  }

  /**
   * Adds a Metadata record (name and key/value pairs: who recorded, where, with which
   * arguments) to the recording. It is written into every file of the recording as the file is
   * finished (each rotated file stands alone), in the order added, before the loss report.
   *
   * @param name the record's name, e.g. {@code prime.process}; not empty, not {@value
   *     #LOSS_METADATA} (the writer's own)
   * @param pairs the key/value pairs (copied)
   * @throws IllegalArgumentException for an empty or reserved name, or a name, key or value with
   *     an unpaired surrogate (not Unicode text, which MCAP's UTF-8 strings cannot hold)
   * @throws NullPointerException for a null key or value
   * @throws IllegalStateException if the writer is closed
   */
  public void metadata(String name, Map<String, String> pairs) {
    checkMetadata(name, pairs);
    Map<String, String> copy = new TreeMap<>(pairs);
    synchronized (definitions) {
      if (closed) {
        throw new IllegalStateException("MCAP writer for " + firstPath + " is closed");
      }
      metadata.add(Map.entry(name, copy));
    }
  }

  /**
   * Refuses a Metadata record that {@link #metadata} would refuse, as it would; for callers that
   * must refuse it before a writer opens (and replaces the recording at its path).
   */
  static void checkMetadata(String name, Map<String, String> pairs) {
    Objects.requireNonNull(name, "name");
    Objects.requireNonNull(pairs, "pairs");
    if (name.isEmpty() || name.equals(LOSS_METADATA)) {
      throw new IllegalArgumentException(
          "a Metadata record's name must not be empty nor '" + LOSS_METADATA
              + "' (the writer's loss report), was '" + name + "'");
    }
    requireUnicode(name, "Metadata record name");
    pairs.forEach((key, value) -> {
      requireUnicode(key, "key of Metadata record '" + name + "'");
      requireUnicode(value, "value of '" + key + "' in Metadata record '" + name + "'");
    });
  }

  /**
   * Refuses a string that UTF-8, the encoding of every MCAP string, cannot hold: one with an
   * unpaired UTF-16 surrogate. Encoding it would write {@code ?} in its place, so that the file
   * would name the topic (or metadata) otherwise than the caller did, and two such topics alike.
   */
  static void requireUnicode(String text, String what) {
    Objects.requireNonNull(text, () -> "a " + what + " is null");
    for (int i = 0; i < text.length(); i++) {
      char c = text.charAt(i);
      if (Character.isHighSurrogate(c) && i + 1 < text.length() && Character.isLowSurrogate(text.charAt(i + 1))) {
        i++;
      } else if (Character.isSurrogate(c)) {
        throw new IllegalArgumentException(String.format(
            "%s '%s' has an unpaired surrogate (U+%04X) at index %d: it is not Unicode text, and"
                + " MCAP strings are UTF-8, which cannot hold it; pass the name as it was meant"
                + " (a surrogate pair, or the character itself)",
            what, text, (int) c, i));
      }
    }
  }

  /**
   * Counts a value that its recorder ({@link McapRecorder}) could not write (no channel type, a
   * message larger than the queue's byte bound, a name past the channel limit), so that the loss
   * record of the file being written says values are missing ({@value #UNWRITABLE_MESSAGES}).
   */
  void countUnwritable() {
    unwritable.increment();
  }

  /** The number of channels defined so far (at most {@link #MAX_CHANNELS}). */
  int channelCount() {
    synchronized (definitions) {
      return channelsByTopic.size();
    }
  }

  /** @return messages dropped so far, on every channel */
  public long droppedCount() {
    return dropped.sum();
  }

  /** @return the files started so far, in order (more than one with rotation) */
  public List<Path> files() {
    return List.copyOf(files);
  }

  /** @return the options */
  public McapWriterOptions options() {
    return options;
  }

  boolean submit(McapChannel<?> channel, long sequence, long logTime, long publishTime, byte[] data) {
    Entry entry = new Entry(channel, sequence, logTime, publishTime, data);
    if (queue == null) {
      // closed is checked under the lock that close() finishes the file under: a write that
      // holds it (waiting for the disk) ends before the file is finished, one after sees closed
      synchronized (syncLock) {
        requireOpen(channel);
        process(entry);
        if (failure != null) {
          throw new UncheckedIOException(
              "writing MCAP file " + currentPath() + " failed: " + failure.getMessage() + "; the writer writes"
                  + " nothing more: close it (its close() says what becomes of the file)",
              failure);
        }
      }
      return true;
    }
    inFlight.incrementAndGet();
    try {
      requireOpen(channel);
      long bytes = data.length;
      if (bytes > options.queueBytes()) {
        throw new IllegalArgumentException(String.format(
            "a message of %d bytes on '%s' is larger than the writer's queue byte bound of %d bytes,"
                + " so it could never be queued: raise the bound with"
                + " McapWriterOptions.queue(messages, bytes), or write synchronously"
                + " (McapWriterOptions.synchronous())",
            bytes, channel.topic(), options.queueBytes()));
      }
      if (queuedBytes.addAndGet(bytes) > options.queueBytes()) {
        queuedBytes.addAndGet(-bytes);
        return drop(channel);
      }
      if (!queue.offer(entry)) {
        queuedBytes.addAndGet(-bytes);
        return drop(channel);
      }
      return true;
    } finally {
      inFlight.decrementAndGet();
    }
  }

  private void requireOpen(McapChannel<?> channel) {
    if (closed) {
      throw new IllegalStateException(
          "MCAP writer for " + firstPath + " is closed: '" + channel.topic() + "' cannot record");
    }
  }

  private boolean drop(McapChannel<?> channel) {
    dropped.increment();
    channel.countDrop();
    return false;
  }

  private void drain() {
    while (true) {
      Entry entry;
      try {
        entry = queue.take();
      } catch (InterruptedException e) {
        // Nobody else holds this thread: an interrupt does not end the recording; close() does.
        continue;
      }
      if (entry == CLOSE) {
        break;
      }
      queuedBytes.addAndGet(-entry.data.length);
      try {
        process(entry);
      } catch (RuntimeException | Error e) {
        // A bug or an exhausted heap must not leave a dead thread behind a full queue.
        if (failure == null) {
          failure = new IOException("the MCAP writer thread failed: " + e, e);
        }
        drop(entry.channel);
      }
    }
    try {
      finishLastFile();
    } finally {
      releaseLock(null);
    }
  }

  /**
   * Finishes the last file; if writing failed, says (in {@link #failedFileFate}) what became of
   * the file being written, having removed or emptied it if this writer discards unfinished
   * files. Called before the path is given up, so that no other writer has opened it.
   */
  private void finishLastFile() {
    finishFile();
    if (failure == null || file == null) {
      return; // finished; or a rotated file failed to open, which its own failure says
    }
    Path path = currentPath();
    String unfinished = "the file is left unfinished, without its summary and footer: McapReader.open refuses"
        + " it, McapReader.openUnfinished reads the records written before the failure"
        + (files.size() > 1 ? "; the recording's files before it are finished" : "");
    if (!discardUnfinished || !fileIsRegular) {
      failedFileFate = unfinished;
      return;
    }
    try {
      if (fileExisted) {
        // no CREATE: a file removed meanwhile is not made again
        FileChannel.open(path, StandardOpenOption.WRITE, StandardOpenOption.TRUNCATE_EXISTING).close();
        failedFileFate = "the file was truncated as the writer opened it, so what it held before is gone;"
            + " it is left empty, not an MCAP file";
      } else {
        Files.deleteIfExists(fileTarget);
        failedFileFate = "the file the writer created is removed" + linkedAs(path, fileTarget) + ", so the path is as it was";
      }
    } catch (IOException e) {
      failure.addSuppressed(e);
      failedFileFate = unfinished + " (it could not be " + (fileExisted ? "emptied" : "removed") + ": " + e + ")";
    }
  }

  /**
   * Gives the recording's path up (once its last file is finished, or when opening failed); a
   * failure to do so is added to {@code failed}'s, or else becomes the writer's failure.
   */
  private void releaseLock(Throwable failed) {
    try {
      lock.release();
    } catch (IOException e) {
      if (failed != null) {
        failed.addSuppressed(e);
      } else if (failure == null) {
        failure = e;
      }
    }
  }

  private void process(Entry entry) {
    if (failure != null) {
      drop(entry.channel);
      return;
    }
    try {
      int channelId = entry.channel.id();
      if (file == null) {
        openNextFile();
      }
      if (!file.hasChannel(channelId)) {
        defineInFile(channelId);
      }
      file.addMessage(channelId, entry.sequence, entry.logTime, entry.publishTime, entry.data);
      if (options.rotateAtSize() > 0 && file.size() >= options.rotateAtSize()) {
        // the next message starts the next file: a recording does not end with an empty one
        finishFile();
        if (failure == null) {
          file = null;
        }
      }
    } catch (IOException e) {
      failure = e;
      drop(entry.channel);
    }
  }

  private void defineInFile(int channelId) {
    McapChannel<?> channel = channelsById.get(channelId);
    int schemaId = schemaOfChannel.get(channelId);
    if (!file.hasSchema(schemaId)) {
      ValueType<?> type = channel.type();
      file.addSchema(schemaId, type.name(), SCHEMA_ENCODING, type.jsonSchema().getBytes(StandardCharsets.UTF_8));
    }
    file.addChannel(channelId, schemaId, channel.topic(), MESSAGE_ENCODING, channelMetadata.get(channelId));
  }

  /**
   * Opens (creates, or truncates) a file and writes its magic and Header. Everything that can be
   * checked is checked before (the options where they are given, the path's holder, the earlier
   * recording's rotated files, and by the open itself the file's permission): a failure here is
   * an I/O error writing the Header, after the truncation. It fails saying what became of the
   * file: one the open created is removed, so the path is as it was; one that existed is left
   * truncated (empty, or with part of the Header), what it held gone.
   */
  private void openFile(Path path) throws IOException {
    // through a symbolic link the open writes (and creates) the file the link leads to: that
    // file existed or not, whatever the link does
    Path target = SymbolicLinks.target(path, "open an MCAP writer at");
    boolean existed = Files.exists(target, LinkOption.NOFOLLOW_LINKS);
    fileExisted = existed;
    fileTarget = target;
    FileChannel channel = opener.open(path);
    try {
      // a device or a pipe (/dev/null) cannot be forced
      fileIsRegular = Files.isRegularFile(path);
      file = new McapFileWriter(channel, options.library(), options.chunkSize(), fileIsRegular);
    } catch (IOException | RuntimeException | Error e) {
      try {
        channel.close();
      } catch (IOException closing) {
        e.addSuppressed(closing);
      }
      if (!(e instanceof IOException failed)) {
        throw e;
      }
      if (!existed) {
        try {
          Files.deleteIfExists(target);
        } catch (IOException deleting) {
          failed.addSuppressed(deleting);
        }
      }
      throw new IOException(
          "could not write the MCAP Header of " + path + ": " + failed.getMessage() + "; "
              + (existed
                  ? "the file was truncated as it was opened, so what it held before is gone and it"
                      + " is left empty (or with part of the Header): not an MCAP file"
                  : "the file the open created is removed" + linkedAs(path, target))
              + "; free the disk (or fix the device) and open the writer again",
          failed);
    }
    files.add(path);
  }

  /** How a message names the file a link leads to: nothing if {@code path} is no link. */
  private static String linkedAs(Path path, Path target) {
    return target.equals(path) ? "" : " (" + target + ", where the symbolic link " + path + " leads; the link stays)";
  }

  /** The next file of a rotated recording. */
  private void openNextFile() throws IOException {
    openFile(rotatedPath(rotationBase, fileIndex + 1));
    fileIndex++;
  }

  private Path currentPath() {
    return files.get(files.size() - 1);
  }

  /**
   * Every channel defined so far, the loss report, the summary and the footer. After a rotation
   * no file is open until the next message: then a file is started only to report messages
   * dropped, or hold Metadata records added, since the last one was finished.
   */
  private void finishFile() {
    if (failure != null) {
      if (file != null) {
        try {
          file.abandon();
        } catch (IOException e) {
          failure.addSuppressed(e);
        }
      }
      return;
    }
    try {
      if (file == null) {
        if (dropped.sum() == droppedAtFileStart && unwritable.sum() == unwritableAtFileStart
            && metadata.size() == metadataAtFileStart) {
          return;
        }
        openNextFile();
      }
      List<Integer> ids = new ArrayList<>(new TreeMap<>(channelsById).keySet());
      for (int id : ids) {
        if (!file.hasChannel(id)) {
          defineInFile(id);
        }
      }
      List<Map.Entry<String, Map<String, String>>> records = List.copyOf(metadata);
      for (Map.Entry<String, Map<String, String>> record : records) {
        file.addMetadata(record.getKey(), record.getValue());
      }
      // counted once: what is dropped after this goes into the next file's report
      long droppedNow = dropped.sum();
      long unwritableNow = unwritable.sum();
      Map<Integer, Long> channelDroppedNow = new HashMap<>();
      Map<String, String> loss = new TreeMap<>();
      loss.put("dropped_messages", Long.toString(droppedNow - droppedAtFileStart));
      loss.put(UNWRITABLE_MESSAGES, Long.toString(unwritableNow - unwritableAtFileStart));
      for (int id : ids) {
        McapChannel<?> channel = channelsById.get(id);
        channelDroppedNow.put(id, channel.droppedCount());
        long lost = channelDroppedNow.get(id) - channelDroppedAtFileStart.getOrDefault(id, 0L);
        loss.put("dropped." + channel.topic(), Long.toString(lost));
      }
      file.addMetadata(LOSS_METADATA, loss);
      file.finish();
      if (fileIsRegular) {
        Durability.forceFolderOf(currentPath(), opener);
      }
      droppedAtFileStart = droppedNow;
      unwritableAtFileStart = unwritableNow;
      channelDroppedAtFileStart.clear();
      channelDroppedAtFileStart.putAll(channelDroppedNow);
      metadataAtFileStart = records.size();
    } catch (IOException e) {
      failure = e;
    }
  }

  /**
   * Waits for the queued messages to be written, then finishes the file: the channels with no
   * message yet, the loss report, the summary and the footer, forced to the storage device with
   * its folder's entry (see "Durability" in the class description), and gives the recording's
   * path up (see "One writer per path"), also when writing failed. Writes after this throw. A close
   * called while another thread's is under way returns once that one has finished the file (so
   * that the file is complete when either returns); a close after that does nothing.
   *
   * @throws IOException if writing failed at any point (the first failure; the message names the
   *     file, which is left unfinished, and says so); an {@link InterruptedIOException} if interrupted while waiting for another
   *     thread's close
   */
  @Override
  public void close() throws IOException {
    boolean first;
    synchronized (definitions) {
      first = !closed;
      closed = true;
    }
    if (!first) {
      awaitClosed();
      return;
    }
    try {
      closeFirst();
    } finally {
      closeFinished.countDown();
    }
  }

  private void awaitClosed() throws InterruptedIOException {
    try {
      closeFinished.await();
      if (thread != null) {
        thread.join(); // the other close may have been interrupted while the file was finished
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new InterruptedIOException(
          "interrupted while another thread closes the MCAP writer for " + firstPath);
    }
  }

  private void closeFirst() throws IOException {
    if (queue == null) {
      // waits (blocked, not spinning) for a write under way, which may wait for the disk
      synchronized (syncLock) {
        try {
          finishLastFile();
        } finally {
          releaseLock(null);
        }
      }
    } else {
      // Writers that passed the closed check finish their offer (it never waits) before the
      // CLOSE mark goes in, so nothing is queued behind it unseen.
      while (inFlight.get() > 0) {
        Thread.yield();
      }
      // Waits for room for the CLOSE mark while the writer thread lives (a stalled disk makes
      // close() wait; a writer thread that died does not make it hang).
      boolean interrupted = false;
      while (thread.isAlive()) {
        try {
          if (queue.offer(CLOSE, 100, TimeUnit.MILLISECONDS)) {
            break;
          }
        } catch (InterruptedException e) {
          interrupted = true;
        }
      }
      if (interrupted) {
        Thread.currentThread().interrupt();
      }
      try {
        thread.join();
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
        throw new InterruptedIOException(
            "interrupted while closing MCAP writer for " + firstPath + "; the writer thread goes on and finishes the file");
      }
    }
    if (failure != null) {
      String fate = failedFileFate;
      throw new IOException(
          fate != null
              ? "writing MCAP file " + currentPath() + " failed: " + failure.getMessage() + "; " + fate
              : "writing the MCAP recording at " + firstPath + " failed: " + failure.getMessage()
                  + (files.isEmpty() ? "" : "; its files up to " + currentPath() + " are finished"),
          failure);
    }
  }
}
