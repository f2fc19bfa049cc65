package dev.prime.mcap;

import dev.prime.RecordedValue;
import dev.prime.Recording;
import java.io.IOException;
import java.nio.file.Path;
import java.time.Instant;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.concurrent.atomic.AtomicReference;
import java.util.concurrent.atomic.LongAdder;
import java.util.logging.Logger;

/**
 * Records a core's {@link Recording} to MCAP continuously: every value, as it is recorded, goes
 * to an {@link McapWriter} with its bounded queue and rotation by size, so a long run keeps every
 * value (the recording's rings keep only the latest few per name) in files of bounded size, and
 * memory stays bounded by the writer's queue. Made by {@link RecordingMcap#stream}.
 *
 * <p>Design note (concurrency): a {@link dev.prime.RecordingListener} on the recording thread
 * encodes the value and offers it to the writer's queue, which never waits: when the writer
 * cannot keep up the value is dropped and counted ({@link #droppedCount()}), never stalling the
 * controller. A name's channel is defined on its first value (typed by that value's class unless
 * a type was given); a name the writer refuses a channel (past the channel limit) is refused
 * once, its later values counted without asking the writer again; likewise a class with no
 * channel type is looked at once (the refusal kept with the class, so values of ever more classes
 * grow no map here), its later values, under any name, counted without another look. A value that cannot be written (no channel type for its class, JSON encoding
 * fails, its message is larger than the queue's byte bound, or its name came after the 65535
 * channels a file holds) is counted in {@link
 * #unwritableCount()} with its first reason. Both losses are in the loss record of the file
 * being written when they happen (its {@code prime.mcap} Metadata record: {@code
 * dropped_messages} and {@code dropped.<topic>} for the drops, {@code unwritable_messages} for the
 * values that could not be written), so a reader of the file alone sees that values are missing.
 * {@link #close()} unsubscribes, flushes the queue, finishes the file and logs a line when
 * anything was lost. A recorder that is never closed goes on recording, and holds its path,
 * as its {@link McapWriter} does, until its JVM exits (see "One writer per path" there).
 */
public final class McapRecorder implements AutoCloseable {
  private static final Logger LOG = Logger.getLogger(McapRecorder.class.getName());

  private final Recording recording;
  private final McapWriter writer;
  private final Map<String, ValueType<?>> types;
  private final ProcessIdentity process;
  private final Map<String, McapChannel<Object>> channels = new ConcurrentHashMap<>();
  /**
   * The names the writer refused a channel (past the channel limit, or a name it cannot hold),
   * with why: their later values are counted as unwritable without asking the writer again.
   */
  private final Map<String, String> refused = new ConcurrentHashMap<>();
  private final LongAdder accepted = new LongAdder();
  private final LongAdder unwritable = new LongAdder();
  private final AtomicReference<String> firstUnwritable = new AtomicReference<>();
  /** Times a value's class was looked at for its channel type ({@link ValueType#of}), for tests. */
  private final LongAdder typeLookups = new LongAdder();
  /** Times a name's channel was looked for in the writer (defined, or refused), for tests. */
  private final LongAdder definitionAttempts = new LongAdder();
  private final Recording.Subscription subscription;
  private final AtomicBoolean closed = new AtomicBoolean();

  McapRecorder(
      Recording recording,
      Path path,
      McapWriterOptions options,
      Map<String, ValueType<?>> types,
      Map<String, Map<String, String>> metadata,
      OutputOpener opener)
      throws IOException {
    this.recording = recording;
    this.types = Map.copyOf(types);
    this.process = ProcessIdentity.current();
    this.writer = McapWriter.open(path, options, opener);
    try {
      writer.metadata(RecordingMcap.PROCESS_METADATA, process.metadata());
      metadata.forEach(writer::metadata);
    } catch (RuntimeException e) {
      writer.close();
      throw e;
    }
    this.subscription = recording.subscribe(this::record);
  }

  private void record(RecordedValue<Object> entry) {
    try {
      recordOrCount(entry);
    } catch (VirtualMachineError e) {
      throw e; // the JVM itself is in trouble
    } catch (RuntimeException | Error e) {
      // what the encoder or a value's own code throws that no rule above foresaw: the value is
      // not written, and counted as the others are, in the file's loss record too (rather than
      // only in the subscription's failures, which no file says)
      unwritable(entry.service() + ": the value could not be written: " + e);
    }
  }

  private void recordOrCount(RecordedValue<Object> entry) {
    McapChannel<Object> channel = channels.get(entry.service());
    if (channel == null) {
      String refusal = refused.get(entry.service());
      if (refusal != null) {
        unwritable(refusal);
        return;
      }
      channel = define(entry);
      if (channel == null) {
        return;
      }
    }
    long time = epochNanos(entry.wallTime());
    try {
      if (channel.write(time, time, entry.sequence(), entry.value())) {
        accepted.increment();
      }
    } catch (IllegalArgumentException | IllegalStateException e) {
      unwritable(entry.service() + ": " + e.getMessage());
    }
  }

  @SuppressWarnings("unchecked")
  private McapChannel<Object> define(RecordedValue<Object> entry) {
    definitionAttempts.increment();
    String name = entry.service();
    if (writer.channelCount() >= McapWriter.MAX_CHANNELS) {
      refuse(name, overLimit(name));
      return null;
    }
    ValueType<?> given = types.get(name);
    Object found = given != null ? given : channelTypes.get(RecordingMcap.channelClass(entry.value()));
    if (found instanceof String refusal) {
      unwritable(
          name + ": values of " + RecordingMcap.channelClass(entry.value()).getName() + " have no channel type ("
              + refusal + "); give its type in RecordingMcap.stream(..., types)");
      return null;
    }
    ValueType<Object> type = (ValueType<Object>) found;
    Map<String, String> metadata = new LinkedHashMap<>();
    metadata.put("prime.service", name);
    if (entry.pseudoname() != null) {
      metadata.put("prime.pseudoname", entry.pseudoname());
    }
    metadata.put(RecordingMcap.PROCESS_METADATA, process.id());
    try {
      McapChannel<Object> channel = writer.channel(name, type, metadata);
      McapChannel<Object> raced = channels.putIfAbsent(name, channel);
      return raced != null ? raced : channel;
    } catch (IllegalArgumentException e) {
      // the channel's type is made: the writer refused the name itself (the channel limit, a
      // name that is not Unicode text), as it will each time
      refuse(name, writer.channelCount() >= McapWriter.MAX_CHANNELS
          ? overLimit(name)
          : name + ": no channel can be defined for it: " + e.getMessage());
      return null;
    } catch (IllegalStateException e) {
      // the writer is closed
      unwritable(name + ": no channel can be defined for it: " + e.getMessage());
      return null;
    }
  }

  /** Why the values of {@code name}, a name recorded after the file's last channel, are not written. */
  private static String overLimit(String name) {
    return name + ": an MCAP file holds at most " + McapWriter.MAX_CHANNELS + " channels (one per name; channel"
        + " ids are 16 bits), and the recording has values under more names: the values of this name, and of"
        + " any later one, are not written; record fewer names in one core (name only the sources and chains"
        + " you need recorded), or stream the recordings of several cores to one file each";
  }

  /** Counts a value of {@code name}, refused a channel, and remembers the refusal for its later ones. */
  private void refuse(String name, String reason) {
    refused.putIfAbsent(name, reason);
    unwritable(reason);
  }

  private void unwritable(String reason) {
    unwritable.increment();
    writer.countUnwritable();
    firstUnwritable.compareAndSet(null, reason);
  }

  /**
   * The channel type of a value's class, or (a String) why it has none, looked at once per class:
   * the later values of a class with no type are counted without another look and the exception
   * it makes. Kept with the class ({@link ClassValue}), not in a map of the recorder's, so that
   * values of ever more classes grow nothing here, and dropped with the recorder.
   */
  private final ClassValue<Object> channelTypes =
      new ClassValue<>() {
        @Override
        protected Object computeValue(Class<?> type) {
          typeLookups.increment();
          try {
            return ValueType.of(type);
          } catch (IllegalArgumentException e) {
            return e.getMessage();
          }
        }
      };

  /** How many times a value's class was looked at for its channel type; a seam for tests. */
  long typeLookups() {
    return typeLookups.sum();
  }

  /** How many times a channel was defined for a name, or tried and refused; a seam for tests. */
  long definitionAttempts() {
    return definitionAttempts.sum();
  }

  /** {@return the recording this recorder writes} */
  public Recording recording() {
    return recording;
  }

  /** {@return values handed to the writer so far (written or about to be)} */
  public long writtenCount() {
    return accepted.sum();
  }

  /** {@return values dropped so far because the writer's queue was full (it could not keep up)} */
  public long droppedCount() {
    return writer.droppedCount();
  }

  /**
   * {@return values that could not be written: no channel type for their class, encoding failed
   * (whatever the encoder or the value's own code threw),
   * a message larger than the queue's byte bound, or a name recorded after the file's last
   * channel (a file holds at most 65535, one per name); each file's loss record counts those of
   * its time as {@code unwritable_messages}}
   */
  public long unwritableCount() {
    return unwritable.sum();
  }

  /** {@return the files written so far: the first, then each rotated one} */
  public List<Path> files() {
    return writer.files();
  }

  /**
   * Stops recording, writes what is queued, finishes the file and logs (at WARNING) what was
   * lost, if anything. Idempotent: a close called while another thread's is under way returns
   * once the file is finished ({@link McapWriter#close()}), and logs nothing more.
   *
   * @throws IOException if writing failed at any point
   */
  @Override
  public void close() throws IOException {
    if (!closed.compareAndSet(false, true)) {
      subscription.close();
      writer.close();
      return;
    }
    subscription.close();
    writer.close();
    long dropped = droppedCount();
    // the values the files' loss records count as unwritable_messages, so the two agree
    long failed = unwritableCount();
    // a failure that reached the subscription (none should: record() counts what it catches) is
    // in no file, so it is named apart
    long failedInRecorder = subscription.failures();
    if (dropped > 0 || failed > 0 || failedInRecorder > 0) {
      LOG.warning(
          "MCAP recording " + writer.files() + ": wrote " + writtenCount() + " values, dropped "
              + dropped + " (the writer could not keep up; see the prime.mcap Metadata record),"
              + " could not write " + failed + " (unwritable_messages there)"
              + (firstUnwritable.get() == null ? "" : " (first: " + firstUnwritable.get() + ")")
              + (failedInRecorder == 0 ? "" : ", and " + failedInRecorder + " failed in the recorder itself (in no file)"));
    }
  }

  private static long epochNanos(Instant time) {
    return Math.addExact(Math.multiplyExact(time.getEpochSecond(), 1_000_000_000L), time.getNano());
  }

  @Override
  public String toString() {
    return "McapRecorder[" + writer.files() + ", written " + writtenCount() + ", dropped "
        + droppedCount() + "]";
  }
}
