package dev.prime.mcap;

import java.io.IOException;
import java.nio.file.Path;

/**
 * A recorder process for {@link CrashRecoveryTest}: writes {@code count} messages synchronously
 * with the given chunk size, prints {@code WROTE count}, then waits to be killed (it never
 * closes the writer).
 */
final class CrashingRecorder {
  private CrashingRecorder() {}

  record Tick(int index, String note) {}

  public static void main(String[] args) throws IOException {
    Path file = Path.of(args[0]);
    int count = Integer.parseInt(args[1]);
    long chunkSize = Long.parseLong(args[2]);
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous().chunkSize(chunkSize));
    McapChannel<Tick> ticks = writer.channel("ticks", Tick.class);
    for (int i = 0; i < count; i++) {
      ticks.write(1_000L * i, 1_000L * i, i, new Tick(i, "tick"));
    }
    System.out.println("WROTE " + count);
    System.out.flush();
    // Wait for the kill; bounded so an abandoned process ends by itself.
    for (int i = 0; i < 600 && System.in.read() >= 0; i++) {
      // keep waiting
    }
  }
}
