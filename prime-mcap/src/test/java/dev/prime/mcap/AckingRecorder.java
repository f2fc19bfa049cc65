package dev.prime.mcap;

import java.io.IOException;
import java.nio.file.Path;

/**
 * A recorder process for {@link CrashRecoveryTest}: writes messages synchronously, one chunk each
 * (so a write returns once its chunk is in the file), and prints {@code ACK i} after write
 * {@code i} returned, until it is killed; bounded in count and in time so an abandoned process
 * ends by itself. Each message's note is {@code noteLength} characters, so that a kill is likely
 * to land while a chunk is being written; a third argument rotates the recording at that size.
 */
final class AckingRecorder {
  private AckingRecorder() {}

  /** The note of message {@code index}: its index repeated, to check that a message read is whole. */
  static String note(int index, int length) {
    StringBuilder note = new StringBuilder(length + 16);
    String unit = index + ";";
    while (note.length() < length) {
      note.append(unit);
    }
    return note.toString();
  }

  public static void main(String[] args) throws IOException {
    Path file = Path.of(args[0]);
    int noteLength = Integer.parseInt(args[1]);
    long rotateAtSize = args.length > 2 ? Long.parseLong(args[2]) : 0;
    long deadline = System.nanoTime() + 120_000_000_000L;
    McapWriterOptions options = McapWriterOptions.defaults().synchronous().chunkSize(1);
    McapWriter writer = McapWriter.open(file, rotateAtSize > 0 ? options.rotateAtSize(rotateAtSize) : options);
    McapChannel<CrashingRecorder.Tick> ticks = writer.channel("ticks", CrashingRecorder.Tick.class);
    for (int i = 0; i < 1_000_000 && System.nanoTime() < deadline; i++) {
      ticks.write(1_000L * i, 1_000L * i, i, new CrashingRecorder.Tick(i, note(i, noteLength)));
      System.out.println("ACK " + i);
      System.out.flush();
    }
  }
}
