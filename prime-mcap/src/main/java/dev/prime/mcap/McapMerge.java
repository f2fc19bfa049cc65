package dev.prime.mcap;

import dev.prime.mcap.internal.McapFileWriter;
import java.io.Closeable;
import java.io.IOException;
import java.io.PrintStream;
import java.io.UncheckedIOException;
import java.nio.channels.FileChannel;
import java.nio.file.AtomicMoveNotSupportedException;
import java.nio.file.FileAlreadyExistsException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.StandardCopyOption;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.Collections;
import java.util.Comparator;
import java.util.HashMap;
import java.util.HashSet;
import java.util.Iterator;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.PriorityQueue;
import java.util.Set;
import java.util.TreeMap;
import java.util.concurrent.ThreadLocalRandom;
import java.util.stream.Collectors;

/**
 * Joins MCAP files into one: the recordings of the processes of one topology (on Optimus each
 * process records what it hosts, {@link RecordingMcap} writes one file per process), or any MCAP
 * files whose channels agree.
 *
 * <pre>{@code
 * McapMerge.merge(List.of(Path.of("robot.mcap"), Path.of("worker.mcap")), Path.of("run.mcap"));
 * }</pre>
 *
 * or from a shell, with prime-mcap and Jackson on the class path:
 *
 * <pre>
 * java -cp ... dev.prime.mcap.McapMerge -o run.mcap robot.mcap worker.mcap
 * </pre>
 *
 * <ul>
 *   <li><b>Channels</b> are unified by topic: the inputs' channels of one topic become one
 *       channel, which must have the same message encoding and the same schema (name, encoding
 *       and bytes) in every input; a topic with two different schemas is refused before anything
 *       is written, naming the topic, both schemas and both files. Equal schemas become one. The
 *       channel's metadata is the first input's, with the keys only later inputs have added, and
 *       {@value #MERGED_FROM} listing the files that had the topic (their paths as given,
 *       comma-separated); an input that is itself a merge gives its own list instead of its
 *       path, so a merge of merges still lists the recordings.
 *   <li><b>Messages</b> come in log-time order, then by sequence number, then in the order the
 *       inputs are given; each keeps its sequence number and times. Log times are compared as
 *       the writers stamped them: for files of several machines, run their clocks in step (NTP
 *       or PTP), or the merged order is only as good as their agreement.
 *   <li><b>Metadata</b>: every Metadata record of every input is copied, with {@value
 *       #MERGED_FROM} (the input's path, as given) added to its pairs unless an earlier merge
 *       added it (then it keeps naming the file it came from), so a merged recording still has
 *       each process's {@code prime.process} (host, pid) and loss report ({@code prime.mcap}); and
 *       one record {@value #INPUT_METADATA} per input: its {@code index}, {@code file}, {@code
 *       library}, {@code messages} and {@code topics}.
 *   <li>The output is a complete MCAP file like {@link McapWriter}'s: uncompressed chunks with
 *       message indexes, a summary with statistics, chunk and metadata indexes.
 *   <li><b>The output is a new file</b>, moved onto the output path once complete (so that a
 *       merge that fails leaves the output as it was; see {@link #merge(List, Path)}), not the
 *       earlier file rewritten in place, as a {@link McapWriter} opened there rewrites it. So a
 *       hard link to the earlier output keeps the earlier contents (it is no longer the output),
 *       and the output has the permissions (those the umask leaves), owner and group of a file
 *       the merging process creates, not the earlier file's: set them again after the merge if
 *       they matter. Through a symbolic link this is the file the link leads to; the link stays.
 * </ul>
 *
 * <p>Memory: the open chunk of the output, plus, per input, the chunks that overlap in time with
 * its current message (see {@link McapReader#messages()}).
 */
public final class McapMerge {
  /** The Metadata record written per input. */
  public static final String INPUT_METADATA = "prime.merge.input";

  /** The key naming the input(s) a copied Metadata record or a channel came from. */
  public static final String MERGED_FROM = "prime.merged_from";

  /** The usage of {@link #main}. */
  public static final String USAGE =
      "usage: McapMerge [--unfinished] -o OUTPUT.mcap INPUT.mcap INPUT.mcap...\n"
          + "  joins MCAP files (each process's recording) into OUTPUT by log time;"
          + " a topic must have the same schema in every input\n"
          + "  --unfinished  also read files whose writer was killed (what their complete chunks"
          + " hold)";

  private McapMerge() {}

  /**
   * What a merge wrote.
   *
   * @param output the merged file
   * @param messages messages written
   * @param messagesByTopic messages written per topic, in the order of the output's channels
   */
  public record Result(Path output, long messages, Map<String, Long> messagesByTopic) {
    /**
     * Copies the map.
     *
     * @param output the merged file
     * @param messages messages written
     * @param messagesByTopic messages written per topic
     */
    public Result {
      messagesByTopic = Collections.unmodifiableMap(new LinkedHashMap<>(messagesByTopic));
    }
  }

  /**
   * How a merge reads and writes: the output's chunk size, and whether inputs whose writer never
   * finished (a process killed with SIGKILL, a machine that lost power) are read for what their
   * complete records hold. Immutable.
   */
  public static final class Options {
    private final long chunkSize;
    private final boolean readUnfinished;

    private Options(long chunkSize, boolean readUnfinished) {
      this.chunkSize = chunkSize;
      this.readUnfinished = readUnfinished;
    }

    /** {@return 1 MiB chunks, finished inputs only} */
    public static Options defaults() {
      return new Options(McapWriterOptions.DEFAULT_CHUNK_SIZE, false);
    }

    /**
     * @param bytes the output's chunk size, 1 byte to 1 GiB, as {@link
     *     McapWriterOptions#chunkSize(long)} takes
     * @return a copy with this chunk size
     * @throws IllegalArgumentException for less than 1 byte or more than 1 GiB
     */
    public Options chunkSize(long bytes) {
      if (bytes < 1 || bytes > (1L << 30)) {
        throw new IllegalArgumentException("chunk size must be 1 byte to 1 GiB, was " + bytes);
      }
      return new Options(bytes, readUnfinished);
    }

    /**
     * Reads every input with {@link McapReader#openUnfinished}: a file whose writer was killed
     * gives the messages of its complete chunks (the open chunk and what was queued are lost), a
     * finished file all of its messages. Each such input's {@value #INPUT_METADATA} record says
     * {@code unfinished=true} and where its complete records end.
     *
     * @return a copy that reads unfinished inputs
     */
    public Options readUnfinished() {
      return new Options(chunkSize, true);
    }

    /** {@return the output's chunk size in bytes} */
    public long chunkSizeBytes() {
      return chunkSize;
    }

    /** {@return whether unfinished inputs are read} */
    public boolean readsUnfinished() {
      return readUnfinished;
    }
  }

  /**
   * Merges finished files into one, with 1 MiB chunks.
   *
   * @param inputs the files, at least one, each a finished MCAP file (a writer that was killed
   *     leaves an unfinished one: see {@link Options#readUnfinished()})
   * @param output the merged file; created or overwritten once the merge is complete (it is
   *     written to a new file beside it first, {@code .OUTPUT.<random>.partial}, under a name no
   *     file there has, so that none of the user's is replaced; forced to the storage device, then
   *     moved into place, and the folder forced): a merge that fails leaves it as it was, and
   *     removes that file, and
   *     one that returned survives a power cut; not one of the inputs. Being a new file, the
   *     output has a new file's permissions, owner and group, not the earlier one's, and a hard
   *     link to the earlier output keeps the earlier contents (see the class description). The
   *     output is a recording of one file: the rotated files of an earlier recording at that path
   *     ({@code run-0001.mcap}... for {@code run.mcap}, up to a gap of more than two names: a file
   *     further on, such as a user's {@code run-2026.mcap}, is none of them and is left) are
   *     deleted just before the move, from the
   *     last one back, as a {@link McapWriter} opened there deletes them, so that {@link
   *     McapReader#recordingFiles} lists the merge alone (a deletion that fails fails the merge,
   *     the earlier recording left without a gap). If it is a symbolic link, the link stays: the
   *     file it leads to is the one replaced (or made), as a writer opened at a link writes that
   *     file, and the merge is refused while a writer writes it; the rotated files deleted are
   *     those named after that file ({@code runs/run-0001.mcap}... for {@code latest.mcap} to
   *     {@code runs/run.mcap}), as a writer opened at the link deletes them (and names its own),
   *     so that the recording read through either name is the merge alone
   * @return what was written
   * @throws IOException if an input cannot be read or the output cannot be written, or a writer
   *     (or another merge), in this JVM or another process, is writing the output path, or a rotated
   *     file of a recording there ({@code run-0001.mcap} for {@code run.mcap}): the message names
   *     the path and that writer (see {@link McapWriter}, "One writer per path")
   * @throws McapFormatException if an input is not a well-formed, finished MCAP file
   * @throws IllegalArgumentException for no inputs, an input given twice, the output among the
   *     inputs, an input that is a rotated file of a recording at the output (one the merge
   *     would delete), or a topic whose
   *     schema (or message encoding) differs between inputs
   */
  public static Result merge(List<Path> inputs, Path output) throws IOException {
    return merge(inputs, output, Options.defaults());
  }

  /**
   * Merges files into one; see {@link #merge(List, Path)}.
   *
   * @param inputs the files, at least one
   * @param output the merged file; not one of the inputs
   * @param options the chunk size, and whether unfinished inputs are read
   * @return what was written
   * @throws IOException if an input cannot be read or the output cannot be written, or a writer
   *     (or another merge), in this JVM or another process, is writing the output path, or a rotated
   *     file of a recording there ({@code run-0001.mcap} for {@code run.mcap}): the message names
   *     the path and that writer (see {@link McapWriter}, "One writer per path")
   * @throws McapFormatException if an input is not well-formed (or, without {@link
   *     Options#readUnfinished()}, not finished)
   * @throws IllegalArgumentException as {@link #merge(List, Path)}
   */
  public static Result merge(List<Path> inputs, Path output, Options options) throws IOException {
    return merge(inputs, output, options, OutputOpener.FILES);
  }

  static Result merge(List<Path> inputs, Path output, Options options, OutputOpener opener) throws IOException {
    Objects.requireNonNull(inputs, "inputs");
    Objects.requireNonNull(output, "output");
    Objects.requireNonNull(options, "options");
    checkPaths(inputs, output);
    // one writer per path: a merge moved into the path of a writer still writing would replace
    // its file, and two merges into one output would write one partial file together
    RecordingLock lock = RecordingLock.acquire(output, "merge into", false);
    Result result;
    try {
      result = mergeHeld(inputs, output, options, opener);
    } catch (IOException | RuntimeException | Error e) {
      try {
        lock.release();
      } catch (IOException releasing) {
        e.addSuppressed(releasing);
      }
      throw e;
    }
    lock.release();
    return result;
  }

  private static Result mergeHeld(List<Path> inputs, Path output, Options options, OutputOpener opener)
      throws IOException {
    try (OpenInputs open = OpenInputs.open(inputs, options.readUnfinished)) {
      Channels channels = Channels.unify(open.readers);
      // a symbolic link at the output stays: the merge replaces the file it leads to, as a
      // writer opened there writes that file
      Path replaced = SymbolicLinks.target(output, "merge into");
      Path partial = createPartial(replaced);
      try {
        Result result;
        try (FileChannel out = OutputFailed.of(() -> opener.open(partial))) {
          // forced before it is moved into place: a power cut after the move must not leave an
          // empty or zero-filled file where an earlier merge was
          McapFileWriter file = OutputFailed.of(() ->
              new McapFileWriter(out, McapWriterOptions.defaults().library() + " merge", options.chunkSize, true));
          result = write(open.readers, channels, file, output);
          OutputFailed.of(() -> {
            file.finish();
            return file;
          });
        }
        // the output is a recording of one file: an earlier recording's rotated files at its path
        // would be listed with it (McapReader.recordingFiles), so they go first, as a writer's do
        McapWriter.deleteEarlierRotatedFiles(replaced);
        OutputFailed.of(() -> {
          moveInPlace(partial, replaced);
          return replaced;
        });
        // the move is a change of the folder's entries: stored once the folder is forced
        Durability.forceFolderOf(output, opener);
        return result;
      } catch (IOException | RuntimeException | Error e) {
        IOException notDeleted = null;
        try {
          Files.deleteIfExists(partial);
        } catch (IOException deleting) {
          notDeleted = deleting;
          e.addSuppressed(deleting);
        }
        if (e instanceof OutputFailed failed) {
          // the channel's own message ("No space left on device") names no file
          IOException named = new IOException(
              "could not write the merge into " + output + ": " + failed.getMessage() + "; it was being written to "
                  + partial + (notDeleted == null ? ", which is removed" : ", which could not be removed (" + notDeleted
                  + "): delete it") + ", and " + output + " is left as it was; free the disk (or fix the device) and"
                  + " merge again",
              failed.getCause());
          for (Throwable suppressed : failed.getSuppressed()) {
            named.addSuppressed(suppressed);
          }
          throw named;
        }
        throw e;
      }
    }
  }

  /**
   * An I/O error writing the merge's own file (not reading an input), told apart so that the
   * merge's failure can name the output and say what became of it.
   */
  private static final class OutputFailed extends IOException {
    private static final long serialVersionUID = 1L;

    OutputFailed(IOException cause) {
      super(cause.getMessage(), cause);
    }

    /** An output step whose I/O error is the output's. */
    @FunctionalInterface
    interface Step<T> {
      T run() throws IOException;
    }

    static <T> T of(Step<T> step) throws OutputFailed {
      try {
        return step.run();
      } catch (OutputFailed e) {
        throw e;
      } catch (IOException e) {
        throw new OutputFailed(e);
      }
    }
  }

  /** How many names {@link #createPartial} tries before it gives up (each taken by another file). */
  private static final int PARTIAL_ATTEMPTS = 100;

  /**
   * Creates the file a merge is written to until it is complete: beside the output (so that it
   * is moved into place within one file system), so that a merge that fails part way (an input
   * found corrupt) leaves neither a half-written file at the output path nor the loss of what was
   * there (an earlier merge). Its name ({@code .run.mcap.<random>.partial}) is one no file there
   * has: it is created new, never opened over a file of the user's, which a fixed name (say
   * {@code run.mcap.partial}) could be. Made with the permissions a new file gets (as a writer's
   * file), not a temporary file's owner-only ones, since it becomes the output.
   */
  private static Path createPartial(Path output) throws IOException {
    String prefix = "." + output.getFileName() + ".";
    for (int attempt = 1; ; attempt++) {
      Path partial = output.resolveSibling(
          prefix + Long.toUnsignedString(ThreadLocalRandom.current().nextLong(), 36) + ".partial");
      try {
        return Files.createFile(partial);
      } catch (FileAlreadyExistsException taken) {
        if (attempt == PARTIAL_ATTEMPTS) {
          throw new IOException("cannot create a file beside " + output + " to write the merge into until it"
              + " is complete: " + PARTIAL_ATTEMPTS + " new names (" + prefix + "<random>.partial) were each"
              + " taken; remove the files named so there, or write the merge to another folder", taken);
        }
      }
    }
  }

  private static void moveInPlace(Path partial, Path output) throws IOException {
    try {
      Files.move(partial, output, StandardCopyOption.REPLACE_EXISTING, StandardCopyOption.ATOMIC_MOVE);
    } catch (AtomicMoveNotSupportedException e) {
      Files.move(partial, output, StandardCopyOption.REPLACE_EXISTING);
    }
  }

  /** The inputs' readers, closed together. */
  private static final class OpenInputs implements Closeable {
    final List<McapReader> readers = new ArrayList<>();

    static OpenInputs open(List<Path> inputs, boolean unfinished) throws IOException {
      OpenInputs open = new OpenInputs();
      try {
        for (Path input : inputs) {
          open.readers.add(unfinished ? McapReader.openUnfinished(input) : McapReader.open(input));
        }
        return open;
      } catch (IOException | RuntimeException e) {
        try {
          open.close();
        } catch (IOException closing) {
          e.addSuppressed(closing);
        }
        throw e;
      }
    }

    @Override
    public void close() throws IOException {
      IOException failure = null;
      for (McapReader reader : readers) {
        try {
          reader.close();
        } catch (IOException e) {
          if (failure == null) {
            failure = e;
          } else {
            failure.addSuppressed(e);
          }
        }
      }
      if (failure != null) {
        throw failure;
      }
    }
  }

  private static void checkPaths(List<Path> inputs, Path output) throws IOException {
    if (inputs.isEmpty()) {
      throw new IllegalArgumentException("merge needs at least one input file");
    }
    Set<Path> seen = new HashSet<>();
    Path out = output.toAbsolutePath().normalize();
    // the rotated files the merge deletes are those of the file it replaces (where a link leads)
    Path replaced = SymbolicLinks.target(output, "merge into").toAbsolutePath().normalize();
    // those it finds there now: from -0001 on, up to a gap of more than two names (see rotatedFilesIn)
    Map<Path, Integer> rotated = new HashMap<>();
    McapWriter.rotatedFilesIn(replaced).forEach((index, file) -> rotated.put(file, index));
    for (Path input : inputs) {
      Objects.requireNonNull(input, "an input path is null");
      Path in = input.toAbsolutePath().normalize();
      if (!seen.add(in)) {
        throw new IllegalArgumentException(
            "input " + input + " is given twice: its messages would be merged twice");
      }
      if (in.equals(out) || (Files.exists(output) && Files.exists(input) && Files.isSameFile(input, output))) {
        throw new IllegalArgumentException(
            "the output " + output + " is also an input: write the merge to another file");
      }
      if (rotated.containsKey(in)) {
        throw new IllegalArgumentException(
            "input " + input + " is rotated file " + rotated.get(in) + " of a recording at "
                + output + (replaced.equals(out) ? "" : " (" + replaced + ", where that symbolic link leads)")
                + ", whose rotated files the merge deletes (the merge is the recording there"
                + " now): write the merge to another file");
      }
    }
  }

  private static Result write(List<McapReader> readers, Channels channels, McapFileWriter file, Path output)
      throws IOException {
    channels.define(file);
    Map<String, Long> counts = new LinkedHashMap<>();
    for (String topic : channels.topics()) {
      counts.put(topic, 0L);
    }
    long[] perInput = new long[readers.size()];
    PriorityQueue<Head> heads = new PriorityQueue<>(Head.ORDER);
    for (int i = 0; i < readers.size(); i++) {
      Head head = new Head(i, readers.get(i).messages().iterator());
      if (head.advance()) {
        heads.add(head);
      }
    }
    long total = 0;
    try {
      while (!heads.isEmpty()) {
        Head head = heads.poll();
        McapMessage m = head.current;
        int id = channels.outputId(head.input, m.channel().id());
        OutputFailed.of(() -> {
          file.addMessage(id, m.sequence(), m.logTime(), m.publishTime(), m.data());
          return file;
        });
        counts.merge(m.channel().topic(), 1L, Long::sum);
        perInput[head.input]++;
        total++;
        if (head.advance()) {
          heads.add(head);
        }
      }
    } catch (UncheckedIOException e) {
      throw e.getCause();
    }
    for (int i = 0; i < readers.size(); i++) {
      McapReader reader = readers.get(i);
      String from = reader.path().toString();
      for (String name : reader.metadataNames()) {
        for (Map<String, String> pairs : reader.metadata(name)) {
          Map<String, String> copy = new TreeMap<>(pairs);
          // a record an earlier merge copied keeps the file it came from
          copy.putIfAbsent(MERGED_FROM, from);
          OutputFailed.of(() -> {
            file.addMetadata(name, copy);
            return file;
          });
        }
      }
    }
    for (int i = 0; i < readers.size(); i++) {
      McapReader reader = readers.get(i);
      Map<String, String> input = new TreeMap<>();
      input.put("index", Integer.toString(i));
      input.put("file", reader.path().toString());
      input.put("library", reader.library());
      input.put("messages", Long.toString(perInput[i]));
      input.put("topics", reader.channels().stream().map(ChannelInfo::topic).collect(Collectors.joining(",")));
      if (reader.unfinishedAt() >= 0) {
        input.put("unfinished", "true");
        input.put("complete_records_end", Long.toString(reader.unfinishedAt()));
      }
      OutputFailed.of(() -> {
        file.addMetadata(INPUT_METADATA, input);
        return file;
      });
    }
    return new Result(output, total, counts);
  }

  /**
   * One input's next message. A reader gives an input's messages of equal log time in file
   * order; they are gathered and taken by sequence number (equal ones in file order), so that
   * the merge's order holds within each input as well as across them.
   */
  private static final class Head {
    static final Comparator<Head> ORDER =
        Comparator.comparingLong((Head h) -> h.current.logTime())
            .thenComparingLong(h -> h.current.sequence())
            .thenComparingInt(h -> h.input);

    final int input;
    final Iterator<McapMessage> messages;
    private final ArrayDeque<McapMessage> sameTime = new ArrayDeque<>();
    private McapMessage lookahead;
    McapMessage current;

    Head(int input, Iterator<McapMessage> messages) {
      this.input = input;
      this.messages = messages;
    }

    boolean advance() {
      if (sameTime.isEmpty()) {
        McapMessage first = lookahead != null ? lookahead : messages.hasNext() ? messages.next() : null;
        lookahead = null;
        if (first == null) {
          return false;
        }
        List<McapMessage> group = new ArrayList<>();
        group.add(first);
        while (messages.hasNext()) {
          McapMessage next = messages.next();
          if (next.logTime() != first.logTime()) {
            lookahead = next;
            break;
          }
          group.add(next);
        }
        group.sort(Comparator.comparingLong(McapMessage::sequence)); // stable: file order for ties
        sameTime.addAll(group);
      }
      current = sameTime.poll();
      return true;
    }
  }

  /** The output's schemas and channels, and each input channel's id in the output. */
  private static final class Channels {
    /** A schema by value: name, encoding and bytes. */
    private record SchemaKey(String name, String encoding, byte[] data) {
      static SchemaKey of(SchemaInfo schema) {
        return new SchemaKey(schema.name(), schema.encoding(), schema.data());
      }

      @Override
      public boolean equals(Object other) {
        return other instanceof SchemaKey key && name.equals(key.name)
            && encoding.equals(key.encoding) && Arrays.equals(data, key.data);
      }

      @Override
      public int hashCode() {
        return Objects.hash(name, encoding, Arrays.hashCode(data));
      }

      @Override
      public String toString() {
        return name + " (" + encoding + ", " + data.length + " bytes)";
      }
    }

    private static final class Unified {
      final int id;
      final String topic;
      final String messageEncoding;
      final SchemaInfo schema; // null: no schema
      final String firstFile;
      final Map<String, String> metadata = new TreeMap<>();
      final List<String> files = new ArrayList<>();

      Unified(int id, ChannelInfo channel, String file) {
        this.id = id;
        this.topic = channel.topic();
        this.messageEncoding = channel.messageEncoding();
        this.schema = channel.schema().orElse(null);
        this.firstFile = file;
      }
    }

    private final Map<String, Unified> byTopic = new LinkedHashMap<>();
    private final Map<SchemaKey, Integer> schemaIds = new LinkedHashMap<>();
    private final Map<SchemaKey, SchemaInfo> schemas = new HashMap<>();
    private final List<Map<Integer, Integer>> outputIds = new ArrayList<>();

    static Channels unify(List<McapReader> readers) {
      Channels channels = new Channels();
      for (McapReader reader : readers) {
        Map<Integer, Integer> ids = new HashMap<>();
        String file = reader.path().toString();
        for (ChannelInfo channel : reader.channels()) {
          Unified unified = channels.byTopic.get(channel.topic());
          if (unified == null) {
            if (channels.byTopic.size() >= 0xFFFF) {
              throw new IllegalArgumentException("the inputs have more than 65535 topics: an MCAP file holds at most 65535 channels");
            }
            unified = new Unified(channels.byTopic.size() + 1, channel, file);
            channels.byTopic.put(channel.topic(), unified);
            if (unified.schema != null) {
              SchemaKey key = SchemaKey.of(unified.schema);
              channels.schemaIds.computeIfAbsent(key, k -> channels.schemaIds.size() + 1);
              channels.schemas.putIfAbsent(key, unified.schema);
            }
          } else {
            checkSame(unified, channel, file);
          }
          channel.metadata().forEach(unified.metadata::putIfAbsent);
          // an input that is itself a merge names the files it had the topic from: kept, so
          // that a merge of merges still lists the recordings
          String from = channel.metadata().getOrDefault(MERGED_FROM, file);
          if (!unified.files.contains(from)) {
            unified.files.add(from);
          }
          ids.put(channel.id(), unified.id);
        }
        channels.outputIds.add(ids);
      }
      return channels;
    }

    private static void checkSame(Unified unified, ChannelInfo channel, String file) {
      SchemaInfo other = channel.schema().orElse(null);
      boolean sameSchema =
          unified.schema == null
              ? other == null
              : other != null && SchemaKey.of(unified.schema).equals(SchemaKey.of(other));
      if (!sameSchema || !unified.messageEncoding.equals(channel.messageEncoding())) {
        throw new IllegalArgumentException(
            "topic '" + unified.topic + "' has two different schemas: " + describe(unified.schema, unified.messageEncoding)
                + " in " + unified.firstFile + " and " + describe(other, channel.messageEncoding()) + " in " + file
                + "; a merged file has one schema per topic: merge recordings of the same program version,"
                + " or record the topic under another name in one of them");
      }
    }

    private static String describe(SchemaInfo schema, String messageEncoding) {
      if (schema == null) {
        return "no schema (" + messageEncoding + " messages)";
      }
      return schema.name() + " (" + schema.encoding() + ", " + schema.data().length + " bytes, "
          + messageEncoding + " messages)";
    }

    List<String> topics() {
      return List.copyOf(byTopic.keySet());
    }

    int outputId(int input, int channelId) {
      return outputIds.get(input).get(channelId);
    }

    void define(McapFileWriter file) {
      for (Map.Entry<SchemaKey, Integer> schema : schemaIds.entrySet()) {
        SchemaInfo info = schemas.get(schema.getKey());
        file.addSchema(schema.getValue(), info.name(), info.encoding(), info.data());
      }
      for (Unified channel : byTopic.values()) {
        int schemaId = channel.schema == null ? 0 : schemaIds.get(SchemaKey.of(channel.schema));
        Map<String, String> metadata = new TreeMap<>(channel.metadata);
        metadata.put(MERGED_FROM, String.join(",", channel.files));
        file.addChannel(channel.id, schemaId, channel.topic, channel.messageEncoding, metadata);
      }
    }
  }

  /**
   * The command line: {@code McapMerge [--unfinished] -o OUTPUT INPUT...}. Exit codes: 0 merged, 1 the merge
   * failed (an input unreadable or malformed, two schemas for a topic), 2 the command line is
   * wrong.
   *
   * @param args the command line
   */
  public static void main(String[] args) {
    int code = run(args, System.out, System.err);
    if (code != 0) {
      System.exit(code);
    }
  }

  /**
   * Runs the command line and returns its exit code; see {@link #main}.
   *
   * @param args the command line
   * @param out receives what was merged
   * @param err receives errors and the usage
   * @return the exit code
   */
  public static int run(String[] args, PrintStream out, PrintStream err) {
    Path output = null;
    Options options = Options.defaults();
    List<Path> inputs = new ArrayList<>();
    for (int i = 0; i < args.length; i++) {
      String arg = args[i];
      if (arg.equals("-h") || arg.equals("--help")) {
        out.println(USAGE);
        return 0;
      }
      if (arg.equals("--unfinished")) {
        options = options.readUnfinished();
      } else if (arg.equals("-o") || arg.equals("--output")) {
        if (i + 1 >= args.length) {
          return usage(err, arg + " needs a file");
        }
        if (output != null) {
          return usage(err, "one output only");
        }
        output = Path.of(args[++i]);
      } else if (arg.startsWith("-")) {
        return usage(err, "unknown option '" + arg + "'");
      } else {
        inputs.add(Path.of(arg));
      }
    }
    if (output == null) {
      return usage(err, "no output: give -o OUTPUT.mcap");
    }
    if (inputs.isEmpty()) {
      return usage(err, "no input files");
    }
    for (Path input : inputs) {
      if (!Files.isRegularFile(input)) {
        return usage(err, "no file '" + input + "'");
      }
    }
    try {
      Result result = merge(inputs, output, options);
      out.println("merged " + counted(result.messages(), "message") + " from "
          + counted(inputs.size(), "file") + " into "
          + output + ": " + result.messagesByTopic().entrySet().stream()
              .map(e -> e.getKey() + " " + e.getValue()).collect(Collectors.joining(", ")));
      return 0;
    } catch (IOException | IllegalArgumentException | UncheckedIOException | McapFormatException e) {
      err.println("error: " + e.getMessage());
      return 1;
    }
  }

  private static String counted(long count, String noun) {
    return count + " " + noun + (count == 1 ? "" : "s");
  }

  private static int usage(PrintStream err, String problem) {
    err.println("error: " + problem);
    err.println(USAGE);
    return 2;
  }
}
