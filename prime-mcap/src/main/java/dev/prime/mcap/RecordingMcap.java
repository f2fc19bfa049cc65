package dev.prime.mcap;

import dev.prime.RecordedValue;
import dev.prime.Recording;
import java.io.IOException;
import java.io.UncheckedIOException;
import java.nio.file.Path;
import java.time.Instant;
import java.util.ArrayList;
import java.util.Comparator;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;

/**
 * Writes a core's {@link Recording} to an MCAP file: one channel per recorded name (the topic is
 * the name in the topology), a message per recorded value with the value's wall-clock time stamp
 * as log and publish time (nanoseconds since the Unix epoch) and its sequence number, in
 * wall-clock order across channels. Each channel's metadata holds {@code prime.service}, {@code
 * prime.pseudoname} (if one was given) and {@code prime.dropped} (values that fell out of the
 * recording's ring before it was written) and {@code prime.process} ({@code pid@host} of the
 * process that recorded it). The file has a Metadata record {@value #PROCESS_METADATA} with the
 * recording process's {@code host}, {@code pid} and {@code process_start}, and any Metadata
 * records the caller adds (say, the run's arguments): a file of each process of an Optimus
 * topology, joined by {@link McapMerge}, keeps what each process was.
 *
 * <p>This adapter lives here, not in {@code prime-core}, so that the core stays free of Jackson:
 * {@code prime-mcap} depends on {@code prime-core}, never the other way round.
 *
 * <p>Two ways: {@link #write} takes a snapshot of what the rings hold now (the latest {@link
 * dev.prime.RecordingOptions#capacity()} values per name), synchronously; {@link #stream} records
 * every value as it is recorded, for as long as the run lasts, through the bounded queue and the
 * rotation by size of an {@link McapWriter}, never stalling the controller (a writer that cannot
 * keep up drops, counted and reported). Use {@link #stream} for long runs.
 *
 * <pre>{@code
 * RecordingMcap.write(core.recording(), Path.of("run.mcap"));
 *
 * try (McapRecorder recorder = RecordingMcap.stream(core.recording(), Path.of("long.mcap"),
 *     McapWriterOptions.defaults().rotateAtSize(256L << 20))) {
 *   ... run ...
 * } // flushed and finished here
 * }</pre>
 */
public final class RecordingMcap {
  /** The name of the Metadata record that says which process recorded the file. */
  public static final String PROCESS_METADATA = "prime.process";

  private RecordingMcap() {}

  /**
   * Starts recording every value {@code recording} records from now on into MCAP files, as it is
   * recorded; see {@link McapRecorder}. Each name's channel is typed by its first value's class
   * (an enum constant with a body of its own: its enum).
   *
   * @param recording the core's recording (not a merged one: it records nothing more)
   * @param path the first file; overwritten if it exists; rotated files are named by {@link
   *     McapWriter#rotatedPath}
   * @param options the writer's queue, chunk size and rotation; must have a queue (not {@link
   *     McapWriterOptions#synchronous()}), so that recording never waits for the disk
   * @return the recorder; close it to flush and finish the file
   * @throws IOException if the file cannot be opened
   * @throws IllegalArgumentException if {@code options} are synchronous
   */
  public static McapRecorder stream(Recording recording, Path path, McapWriterOptions options)
      throws IOException {
    return stream(recording, path, options, Map.of(), Map.of());
  }

  /**
   * Like {@link #stream(Recording, Path, McapWriterOptions)}, with channel types given for some
   * names and Metadata records of the caller's.
   *
   * @param recording the core's recording
   * @param path the first file; overwritten if it exists
   * @param options the writer's options; must have a queue
   * @param types the value type of a name's channel, e.g. for a generic class; names not in it
   *     are typed by their first value's class
   * @param metadata Metadata records to add, by name; not {@value #PROCESS_METADATA} nor {@value
   *     McapWriter#LOSS_METADATA}
   * @return the recorder; close it to flush and finish the file
   * @throws IOException if the file cannot be opened
   * @throws IllegalArgumentException if {@code options} are synchronous or a metadata name is
   *     reserved or empty (a type given for a name never recorded is never used)
   * @throws NullPointerException if an argument, or a name or type in {@code types}, is null
   *     (refused before the path is touched)
   */
  public static McapRecorder stream(
      Recording recording,
      Path path,
      McapWriterOptions options,
      Map<String, ValueType<?>> types,
      Map<String, Map<String, String>> metadata)
      throws IOException {
    return stream(recording, path, options, types, metadata, OutputOpener.FILES);
  }

  static McapRecorder stream(
      Recording recording,
      Path path,
      McapWriterOptions options,
      Map<String, ValueType<?>> types,
      Map<String, Map<String, String>> metadata,
      OutputOpener opener)
      throws IOException {
    Objects.requireNonNull(recording, "recording must not be null");
    Objects.requireNonNull(path, "path must not be null");
    Objects.requireNonNull(options, "options must not be null");
    Objects.requireNonNull(types, "types must not be null");
    Objects.requireNonNull(metadata, "metadata must not be null");
    if (options.isSynchronous()) {
      throw new IllegalArgumentException(
          "a streaming recorder needs a writer with a queue, so that recording never waits for"
              + " the disk; use McapWriterOptions.defaults() (or .queue(messages, bytes)), not"
              + " synchronous()");
    }
    checkTypes(types);
    checkMetadata(metadata);
    return new McapRecorder(recording, path, options, types, metadata, opener);
  }

  /**
   * Writes what {@code recording} holds now, typing each channel by the class of its first value
   * (a record, an enum, a boxed primitive, a String...). Names with nothing recorded get no
   * channel.
   *
   * @param recording the recording
   * @param path the file; overwritten if it exists
   * @return the number of messages written
   * @throws IOException if the file cannot be written
   * @throws IllegalArgumentException if a value's class cannot be a channel's type by itself (a
   *     generic class such as a {@code List}): give its type with {@link #write(Recording, Path,
   *     Map)}
   */
  public static long write(Recording recording, Path path) throws IOException {
    return write(recording, path, Map.of());
  }

  /**
   * Writes what {@code recording} holds now, with the channel types given for some names.
   *
   * @param recording the recording
   * @param path the file; overwritten if it exists
   * @param types the value type of a name's channel, e.g. {@code Map.of("plan", new
   *     ValueType<List<Pose>>() {})}; names not in it are typed by their first value's class
   * @return the number of messages written
   * @throws IOException if the file cannot be written
   * @throws IllegalArgumentException if {@code types} names a name that is not recorded, or a
   *     channel's type cannot be made from its first value's class
   */
  public static long write(Recording recording, Path path, Map<String, ValueType<?>> types)
      throws IOException {
    return write(recording, path, types, Map.of());
  }

  /**
   * Writes what {@code recording} holds now, with the channel types given for some names and
   * Metadata records of the caller's (what a replay needs to reproduce the run: its goal, its
   * arguments).
   *
   * <pre>{@code
   * RecordingMcap.write(core.recording(), path, Map.of(), Map.of("robot.run", Map.of("goal", "2,1")));
   * }</pre>
   *
   * @param recording the recording
   * @param path the file; overwritten if it exists
   * @param types the value type of a name's channel; names not in it are typed by their first
   *     value's class
   * @param metadata Metadata records to add, by name (read back with {@link
   *     McapReader#metadata(String)}); not {@value #PROCESS_METADATA} nor {@value
   *     McapWriter#LOSS_METADATA}, which are written anyway
   * @return the number of messages written
   * @throws IOException if the file cannot be written: a failure after its Header (a full disk)
   *     names the file and says what became of it: removed if this write created it (the path is
   *     as it was; at a symbolic link to a file not there yet, the file made where it leads), or
   *     else left empty (what it held was gone once the writer truncated it), so
   *     that no unfinished file is left for a reader to take as the recording
   * @throws IllegalArgumentException if {@code types} names a name that is not recorded, a
   *     channel's type cannot be made from its first value's class, a name with no type given has
   *     values of more than one class, a value does not fit the type given for its name (or its
   *     wall-clock time is before 1970), values are recorded under more names than the 65535
   *     channels a file holds, a recorded name or pseudoname is not Unicode text (an
   *     unpaired surrogate, which MCAP's UTF-8 strings cannot hold), or a metadata name is
   *     reserved or empty: each is refused before the file at the path is touched, so a file
   *     already there stays as it was
   * @throws NullPointerException if an argument, or a name or type in {@code types}, is null
   *     (also refused before the path is touched)
   */
  public static long write(
      Recording recording,
      Path path,
      Map<String, ValueType<?>> types,
      Map<String, Map<String, String>> metadata)
      throws IOException {
    return write(recording, path, types, metadata, OutputOpener.FILES);
  }

  static long write(
      Recording recording,
      Path path,
      Map<String, ValueType<?>> types,
      Map<String, Map<String, String>> metadata,
      OutputOpener opener)
      throws IOException {
    Objects.requireNonNull(recording, "recording must not be null");
    Objects.requireNonNull(path, "path must not be null");
    Objects.requireNonNull(types, "types must not be null");
    Objects.requireNonNull(metadata, "metadata must not be null");
    checkTypes(types);
    checkMetadata(metadata);
    for (String name : types.keySet()) {
      if (!recording.names().contains(name)) {
        throw new IllegalArgumentException(
            "a type is given for '" + name + "', which is not recorded; recorded names: "
                + recording.names());
      }
    }
    Map<String, List<RecordedValue<Object>>> byName = new LinkedHashMap<>();
    List<RecordedValue<Object>> all = new ArrayList<>();
    for (String name : recording.names()) {
      List<RecordedValue<Object>> entries = recording.getAllStamped(name);
      if (!entries.isEmpty()) {
        byName.put(name, entries);
        all.addAll(entries);
      }
    }
    if (byName.size() > McapWriter.MAX_CHANNELS) {
      // the writer would refuse the 65536th channel only after it replaced the file at the path
      throw new IllegalArgumentException(
          "the recording has values under " + byName.size() + " names, and an MCAP file holds at most "
              + McapWriter.MAX_CHANNELS + " channels (one per name; channel ids are 16 bits): record"
              + " fewer names in one core (name only the sources and chains you need recorded), or"
              + " write the recordings of several cores to one file each");
    }
    all.sort(Comparator.comparing(RecordedValue::wallTime));
    // Everything the writer would refuse is refused here, before the file at the path is
    // replaced: every channel's type, topic and metadata, and every value, encoded now (the
    // writer then writes those bytes) with its time.
    ProcessIdentity process = ProcessIdentity.current();
    Map<String, ValueType<Object>> channelTypes = new LinkedHashMap<>();
    Map<String, Map<String, String>> channelMetadata = new LinkedHashMap<>();
    byName.forEach((name, entries) -> {
      channelTypes.put(name, type(name, types.get(name), entries.get(0)));
      if (!types.containsKey(name)) {
        requireOneClass(name, entries);
      }
      Map<String, String> pairs = channelMetadata(recording, name, process);
      McapWriter.checkChannel(name, pairs);
      channelMetadata.put(name, pairs);
    });
    List<byte[]> encoded = new ArrayList<>(all.size());
    long[] times = new long[all.size()];
    for (int i = 0; i < all.size(); i++) {
      RecordedValue<Object> entry = all.get(i);
      ValueType<Object> type = channelTypes.get(entry.service());
      try {
        times[i] = epochNanos(entry.wallTime());
        McapChannel.checkTimes(entry.service(), times[i], times[i]);
        encoded.add(type.toJson(entry.value()));
      } catch (IllegalArgumentException | ArithmeticException e) {
        throw new IllegalArgumentException(
            "value " + entry.sequence() + " recorded under '" + entry.service() + "' ("
                + entry.value().getClass().getName() + ", at " + entry.wallTime() + ") cannot be"
                + " written as " + type.name() + ": " + e.getMessage() + "; give a type its values"
                + " fit in RecordingMcap.write(recording, path, types), or none to type the channel"
                + " by its first value's class",
            e);
      }
    }
    long written = 0;
    // a failure to write (a full disk) after the Header removes the file if this write created
    // it, or else leaves it empty: no unfinished file a reader could take for the recording
    try (McapWriter writer =
        McapWriter.open(path, McapWriterOptions.defaults().synchronous(), opener, true)) {
      writer.metadata(PROCESS_METADATA, process.metadata());
      metadata.forEach(writer::metadata);
      Map<String, McapChannel<Object>> channels = new LinkedHashMap<>();
      channelTypes.forEach(
          (name, type) -> channels.put(name, writer.channel(name, type, channelMetadata.get(name))));
      for (int i = 0; i < all.size(); i++) {
        RecordedValue<Object> entry = all.get(i);
        try {
          if (channels.get(entry.service()).writeJson(times[i], times[i], entry.sequence(), encoded.get(i))) {
            written++;
          }
        } catch (UncheckedIOException failed) {
          break; // the writer keeps the failure: its close, next, throws it, saying what became of the file
        }
      }
    }
    return written;
  }

  /** Refuses a null name or type in {@code types}, naming it, before the path is touched. */
  private static void checkTypes(Map<String, ValueType<?>> types) {
    types.forEach((name, type) -> {
      Objects.requireNonNull(name, "a name in types must not be null: give the recorded names");
      Objects.requireNonNull(type, () -> "the type given for '" + name + "' must not be null: give its"
          + " ValueType, or leave '" + name + "' out of types to type its channel by its first"
          + " value's class");
    });
  }

  /**
   * Refuses, before a writer opens and replaces the recording at the path, Metadata records that
   * RecordingMcap writes itself or that the writer would refuse.
   */
  private static void checkMetadata(Map<String, Map<String, String>> metadata) {
    if (metadata.containsKey(PROCESS_METADATA)) {
      throw new IllegalArgumentException(
          "the Metadata record '" + PROCESS_METADATA + "' is written by RecordingMcap itself;"
              + " give your records other names");
    }
    metadata.forEach(McapWriter::checkMetadata);
  }

  /**
   * Refuses a name whose values (its channel typed by the first one's class) are of more than one
   * class: another class's values cannot be written as that type.
   */
  private static void requireOneClass(String name, List<RecordedValue<Object>> entries) {
    Class<?> first = channelClass(entries.get(0).value());
    for (RecordedValue<Object> entry : entries) {
      Class<?> other = channelClass(entry.value());
      if (other != first) {
        throw new IllegalArgumentException(
            "the values recorded under '" + name + "' are of more than one class: " + first.getName()
                + ", and " + other.getName() + " (value " + entry.sequence() + "); a channel has one"
                + " type: have the block give values of one class (a record, say), or give the"
                + " type of '" + name + "' in RecordingMcap.write(recording, path, types)");
      }
    }
  }

  private static Map<String, String> channelMetadata(
      Recording recording, String name, ProcessIdentity process) {
    Map<String, String> metadata = new LinkedHashMap<>();
    metadata.put("prime.service", name);
    recording.pseudoname(name).ifPresent(p -> metadata.put("prime.pseudoname", p));
    metadata.put("prime.dropped", Long.toString(recording.dropped(name)));
    metadata.put(PROCESS_METADATA, process.id());
    return metadata;
  }

  @SuppressWarnings("unchecked")
  private static ValueType<Object> type(
      String name, ValueType<?> given, RecordedValue<Object> first) {
    if (given != null) {
      return (ValueType<Object>) given;
    }
    Class<?> type = channelClass(first.value());
    try {
      return (ValueType<Object>) ValueType.of(type);
    } catch (IllegalArgumentException unsupported) {
      throw new IllegalArgumentException(
          "the values recorded under '" + name + "' are " + type.getName() + ", which is not a"
              + " channel type by itself (" + unsupported.getMessage() + "); give the type of '"
              + name + "' in RecordingMcap.write(recording, path, types)",
          unsupported);
    }
  }

  /**
   * The class that types a channel whose first value is {@code value}: its class, or for an enum
   * constant with a body of its own (an instance of an anonymous subclass, which is not itself an
   * enum) the enum.
   */
  static Class<?> channelClass(Object value) {
    return value instanceof Enum<?> constant ? constant.getDeclaringClass() : value.getClass();
  }

  private static long epochNanos(Instant time) {
    return Math.addExact(Math.multiplyExact(time.getEpochSecond(), 1_000_000_000L), time.getNano());
  }
}
