package dev.prime.mcap;

import java.io.IOException;
import java.nio.ByteBuffer;
import java.nio.channels.FileChannel;
import java.nio.channels.FileLock;
import java.nio.channels.OverlappingFileLockException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.NoSuchFileException;
import java.nio.file.Path;
import java.nio.file.StandardOpenOption;
import java.nio.file.attribute.BasicFileAttributes;
import java.time.Instant;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.concurrent.ConcurrentHashMap;
import java.util.stream.Stream;

/**
 * Holds the path of a recording for one {@link McapWriter} (or a {@link McapMerge} into it), so
 * that a second writer there (which would truncate the first one's file, delete its rotated files
 * and interleave its records with the first one's, or a merge replace it) is refused instead.
 *
 * <p>Across processes: an advisory lock ({@link FileChannel#tryLock()}) on {@code <first>.lock}
 * beside the recording, holding a line that names the holder (pid, host, thread, since when).
 * The operating system releases it when its process dies, so a lock file a killed process left
 * does not stop a new writer. In this JVM: a registry of the held paths, checked before the lock
 * file is opened, because file locks belong to the whole JVM and closing any channel of the JVM
 * on the lock file would release the lock (POSIX semantics).
 *
 * <p>A writer's recording is more than its first file: it deletes the rotated files of an earlier
 * recording at its path when it opens, and truncates each next one as it rotates ({@link
 * McapWriter#rotatedPath}). So a writer is also refused where its files and another holder's
 * overlap: at {@code run-0001.mcap} while a writer at {@code run.mcap} holds that recording, and
 * at {@code run.mcap} while a writer (or merge) holds {@code run-0001.mcap}; and so is a merge
 * into {@code run.mcap} then, whose output would be read as the first file of a recording whose
 * second is still being written. Each holder locks its
 * own lock file first, then looks at the lock files of the overlapping paths, read only with a
 * shared lock, so that another user's lock file can be looked at (a lock it can take there is no
 * holder's: it is let go at once), so two of them opened at once cannot both miss
 * each other. In this JVM, taking and giving up holds is serialized, so that such a look never
 * closes a channel on a lock file that a writer of this JVM holds.
 *
 * <p>A writer opened at a symbolic link writes the file it links to, and a merge into a link
 * replaces that file: it holds that file's path too ({@code <target>.lock}), so that writers (and
 * merges) at the file and at links to it refuse each other; a writer's rotated files are then
 * named after that file, so its overlaps are looked for as for a writer there, and not as for a
 * writer at the link: a writer at {@code latest-0001.mcap} beside a link {@code latest.mcap} to
 * {@code runs/run.mcap} shares no file with a writer at the link, and neither refuses the other
 * (whether the path is a link is looked at as a holder opens).
 *
 * <p>A path that is a device or a pipe ({@code /dev/null}) is not held. Released by the writer
 * once its last file is finished: the lock file is deleted (while still
 * locked), then closed. A writer that took the lock file just before it was deleted sees that the
 * path no longer names the file it locked, and takes the new one.
 */
final class RecordingLock {
  private static final Map<Path, String> HELD_IN_THIS_JVM = new ConcurrentHashMap<>();
  private static final int ATTEMPTS = 10;
  private static final String LOCK_SUFFIX = ".lock";

  private final Path key;
  private final Path lockFile;
  private final String holder;
  private final FileChannel channel;
  /**
   * The hold on the file a writer's path is a symbolic link to, taken with this one; null if none.
   * Set and read under the class's lock.
   */
  private RecordingLock target;

  private RecordingLock(Path key, Path lockFile, String holder, FileChannel channel) {
    this.key = key;
    this.lockFile = lockFile;
    this.holder = holder;
    this.channel = channel;
  }

  /** The lock file of the recording whose first file is {@code first}: {@code <first>.lock}. */
  static Path lockPath(Path first) {
    return first.resolveSibling(first.getFileName() + LOCK_SUFFIX);
  }

  /**
   * Takes the recording at {@code first} for the calling writer (or merge).
   *
   * @param first the recording's (first) file
   * @param action what the caller is about to do, for the refusal: "open an MCAP writer at"
   * @param rotatedFiles whether the caller also writes (and deletes) the rotated files of {@code
   *     first} (a writer), or only {@code first} itself (a merge's output); either is refused while
   *     a rotated file of {@code first} is held, which would be read as part of its recording
   * @throws IOException naming the path and the holder if another writer holds it, or holds a path
   *     whose files overlap with the caller's, or if the lock file cannot be made; naming the path
   *     and the fix, before anything is made, if it is a loop of symbolic links
   */
  static RecordingLock acquire(Path first, String action, boolean rotatedFiles) throws IOException {
    // a loop of links is refused before anything is made (the lock file)
    Path linked = linkTarget(first, action);
    if (Files.exists(first) && !Files.isRegularFile(first) && !Files.isDirectory(first)) {
      // a device or a pipe (/dev/null for a benchmark): no recording a second writer could
      // truncate, and no folder of its own to put a lock file in
      return new RecordingLock(null, null, null, null);
    }
    synchronized (RecordingLock.class) {
      RecordingLock lock = take(first, action);
      try {
        refuseOverlaps(first, action, rotatedFiles);
        // a writer writes through a symbolic link into the file it names, and a merge replaces
        // that file (the link stays): that file is held too
        if (linked != null) {
          try {
            lock.target = take(linked, action);
            refuseOverlaps(linked, action, rotatedFiles);
          } catch (IOException e) {
            throw new IOException("cannot " + action + " " + first + ", a symbolic link to " + linked + ": "
                + e.getMessage(), e);
          }
        }
      } catch (IOException | RuntimeException e) {
        try {
          lock.release();
        } catch (IOException releasing) {
          e.addSuppressed(releasing);
        }
        throw e;
      }
      return lock;
    }
  }

  /**
   * Refuses a recording at {@code first} whose files overlap with those of a recording held
   * (after {@code first}'s own lock is taken, so that of two such writers opened at once, the
   * later look finds the other one's lock).
   */
  private static void refuseOverlaps(Path first, String action, boolean rotatedFiles) throws IOException {
    Path recording = McapWriter.recordingOf(first);
    // a writer at a symbolic link (latest.mcap to runs/run.mcap) rotates into the files named
    // after the file it leads to (runs/run-0001.mcap), not after the link (latest-0001.mcap):
    // its overlaps are those of a writer at that file, looked for there
    if (recording != null && !leadsElsewhere(recording)) {
      String holder = holderOf(recording);
      if (holder != null) {
        throw new IOException("cannot " + action + " " + first + ": " + holder + " is writing the recording at "
            + recording + ", whose rotated file " + McapWriter.rotationIndex(recording, first) + " is " + first
            + " (it holds " + lockPath(recording) + "); a writer there truncates its rotated files as it rotates"
            + " into them (a merge there makes the recording's files anew), so the two would destroy each"
            + " other's files: close the other writer or let the merge end (or end its process) first, or"
            + " write to another path");
      }
    }
    Path folder = first.toAbsolutePath().getParent();
    if (folder == null || !Files.isDirectory(folder) || leadsElsewhere(first)) {
      return;
    }
    List<Path> rotated = new ArrayList<>();
    try (Stream<Path> siblings = Files.list(folder)) {
      for (Path sibling : (Iterable<Path>) siblings::iterator) {
        String name = sibling.getFileName().toString();
        if (name.endsWith(LOCK_SUFFIX)) {
          Path file = first.resolveSibling(name.substring(0, name.length() - LOCK_SUFFIX.length()));
          if (!name.equals(LOCK_SUFFIX) && McapWriter.rotationIndex(first, file) > 0) {
            rotated.add(file);
          }
        }
      }
    }
    for (Path file : rotated) {
      String holder = holderOf(file);
      if (holder != null) {
        String why = rotatedFiles
            ? "a writer at " + first + " deletes the rotated files of an earlier recording there and truncates"
                + " them as it rotates, so the two would destroy each other's files"
            : "McapReader.recordingFiles(" + first + ") would list that file, still being written, as part of"
                + " the recording at " + first;
        throw new IOException("cannot " + action + " " + first + ": " + holder + " is writing " + file
            + ", which is rotated file " + McapWriter.rotationIndex(first, file) + " of a recording at " + first
            + " (it holds " + lockPath(file) + "); " + why
            + ": close the other writer (or end its process) first, or write to another path");
      }
    }
  }

  /**
   * Who holds the recording at {@code first}, for a refusal; null if nobody does (no lock file, or
   * one whose process died: its lock, taken here to see, is let go at once).
   */
  private static String holderOf(Path first) throws IOException {
    Path lockFile = lockPath(first);
    String inThisJvm = HELD_IN_THIS_JVM.get(key(lockFile));
    if (inThisJvm != null) {
      return "another writer in this JVM (" + inThisJvm + ")";
    }
    // read only, with a shared lock: the look needs no right to write another user's lock file,
    // and a holder's exclusive lock refuses a shared one as it does an exclusive one
    FileChannel channel;
    try {
      channel = FileChannel.open(lockFile, StandardOpenOption.READ);
    } catch (NoSuchFileException e) {
      return null;
    } catch (IOException e) {
      throw new IOException("cannot tell whether a writer is writing " + first + ": its lock file " + lockFile
          + " cannot be read (" + e + "); if no writer is writing " + first + ", delete " + lockFile
          + ", else make it readable to this user, or write to another path", e);
    }
    try (FileChannel open = channel) {
      FileLock lock;
      try {
        lock = open.tryLock(0, Long.MAX_VALUE, true);
      } catch (OverlappingFileLockException e) {
        lock = null; // another channel of this JVM holds it (not through this class)
      }
      if (lock != null) {
        return null; // nobody's: let go as the channel closes (no other channel of this JVM is open on it)
      }
      String text = contents(open);
      return text.isBlank() ? "another process" : "another writer (" + text + ")";
    }
  }

  /** Takes the lock file of the recording at {@code first}, refusing if another writer holds it. */
  private static RecordingLock take(Path first, String action) throws IOException {
    Path lockFile = lockPath(first);
    Path key = key(lockFile);
    ProcessIdentity self = ProcessIdentity.current();
    String holder = "pid " + self.pid() + " on " + self.host() + ", thread \"" + Thread.currentThread().getName()
        + "\", since " + Instant.now();
    String other = HELD_IN_THIS_JVM.putIfAbsent(key, holder);
    if (other != null) {
      throw held(action, first, lockFile, "another writer in this JVM (" + other + ")");
    }
    try {
      for (int attempt = 1; ; attempt++) {
        Object before = fileKey(lockFile);
        FileChannel channel;
        try {
          channel = FileChannel.open(lockFile, StandardOpenOption.CREATE, StandardOpenOption.READ,
              StandardOpenOption.WRITE);
        } catch (NoSuchFileException e) {
          throw e; // no folder: the writer's own file cannot be made either, and says so
        } catch (IOException e) {
          throw new IOException("cannot " + action + " " + first + ": its lock file " + lockFile
              + " (which holds the recording for one writer) cannot be created or opened to read and write ("
              + e + "); if no writer is writing " + first + ", delete " + lockFile + " (a writer of another"
              + " user that was killed may have left it), else make the folder and that file writable to this"
              + " user, or write to another path", e);
        }
        try {
          FileLock lock;
          try {
            lock = channel.tryLock();
          } catch (OverlappingFileLockException e) {
            lock = null; // another channel of this JVM holds it (not through this class)
          }
          if (lock == null) {
            String text = contents(channel);
            throw held(action, first, lockFile, text.isBlank() ? "another process" : "another writer (" + text + ")");
          }
          Object after = fileKey(lockFile);
          if (after != null && after.equals(before)) {
            channel.truncate(0);
            channel.write(ByteBuffer.wrap((holder + "\n").getBytes(StandardCharsets.UTF_8)), 0);
            return new RecordingLock(key, lockFile, holder, channel);
          }
          if (after == null && before == null && attempt > 1) {
            // no file key on this file system: the lock is taken as it is
            channel.truncate(0);
            channel.write(ByteBuffer.wrap((holder + "\n").getBytes(StandardCharsets.UTF_8)), 0);
            return new RecordingLock(key, lockFile, holder, channel);
          }
        } catch (IOException | RuntimeException e) {
          channel.close();
          throw e;
        }
        // the lock file was created, or deleted by the writer that held it, meanwhile: again
        channel.close();
        if (attempt >= ATTEMPTS) {
          throw new IOException("cannot take the lock file " + lockFile + " of the MCAP recording " + first
              + ": it was replaced " + ATTEMPTS + " times while being taken (writers opening and closing there"
              + " in a loop); open the writer again once they are done");
        }
      }
    } catch (IOException | RuntimeException e) {
      HELD_IN_THIS_JVM.remove(key, holder);
      throw e;
    }
  }

  /** Gives the recording up: deletes the lock file while holding it, then releases it. */
  void release() throws IOException {
    if (channel == null) {
      return;
    }
    synchronized (RecordingLock.class) {
      releaseHeld();
    }
  }

  private void releaseHeld() throws IOException {
    try {
      Files.deleteIfExists(lockFile);
    } finally {
      try {
        channel.close();
      } finally {
        HELD_IN_THIS_JVM.remove(key, holder);
        if (target != null) {
          target.releaseHeld();
        }
      }
    }
  }

  /**
   * The file that {@code first} is a symbolic link to (followed through links to links, whether
   * it exists yet or not), if its lock file is not {@code first}'s own; null if {@code first} is
   * no link.
   *
   * @throws IOException for a loop of links (see {@link SymbolicLinks#target})
   */
  private static Path linkTarget(Path first, String action) throws IOException {
    Path path = SymbolicLinks.target(first, action);
    return path.equals(first) || key(lockPath(path)).equals(key(lockPath(first))) ? null : path;
  }

  /**
   * Whether {@code path} is a symbolic link to a file of another lock file, whose name a writer
   * there names its rotated files after; false if not, or if that cannot be told (a loop of
   * links: then its overlaps are looked for as a file's, the safer way).
   */
  private static boolean leadsElsewhere(Path path) {
    try {
      return linkTarget(path, "look at") != null;
    } catch (IOException e) {
      return false;
    }
  }

  private static IOException held(String action, Path first, Path lockFile, String holder) {
    return new IOException("cannot " + action + " " + first + ": " + holder + " is writing that recording"
        + " (it holds " + lockFile + "); two writers at one path would truncate and interleave each other's"
        + " files: close the other writer (or end its process) first, or write to another path");
  }

  /** The lock file's path, the same for every spelling of it (relative, through a symbolic link). */
  private static Path key(Path lockFile) throws IOException {
    Path absolute = lockFile.toAbsolutePath().normalize();
    Path parent = absolute.getParent();
    if (parent != null && Files.isDirectory(parent)) {
      return parent.toRealPath().resolve(Objects.requireNonNull(absolute.getFileName()));
    }
    return absolute;
  }

  /** The identity (device and inode) of the file at {@code path}, or null if there is none. */
  private static Object fileKey(Path path) throws IOException {
    try {
      return Files.readAttributes(path, BasicFileAttributes.class).fileKey();
    } catch (NoSuchFileException e) {
      return null;
    }
  }

  /** What the holder wrote in the lock file (its first line, bounded), read through {@code channel}. */
  private static String contents(FileChannel channel) throws IOException {
    ByteBuffer buffer = ByteBuffer.allocate(512);
    while (buffer.hasRemaining() && channel.read(buffer, buffer.position()) > 0) {
      // read on, up to the buffer's size
    }
    String text = new String(buffer.array(), 0, buffer.position(), StandardCharsets.UTF_8);
    int newline = text.indexOf('\n');
    return (newline >= 0 ? text.substring(0, newline) : text).strip();
  }
}
