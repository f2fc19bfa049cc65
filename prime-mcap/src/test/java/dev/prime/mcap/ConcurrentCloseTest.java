package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assertions.fail;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.nio.file.Path;
import java.util.Map;
import java.util.EnumSet;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * {@link McapWriter#close()} called by two threads at once (a stop command and a
 * try-with-resources, say): the second call returns once the file is finished, as the first
 * does, not at once while the first is still writing it; a caller that reads the file after its
 * close returned finds it complete.
 */
class ConcurrentCloseTest {
  @TempDir Path dir;

  record Sample(int value) {}

  private static final EnumSet<Thread.State> WAITING =
      EnumSet.of(Thread.State.WAITING, Thread.State.TIMED_WAITING, Thread.State.BLOCKED);

  /** A thread that closes the writer; its future completes when close() returns. */
  private static Thread closer(AutoCloseable writer, CompletableFuture<Void> done, String name) {
    Thread thread = new Thread(() -> {
      try {
        writer.close();
        done.complete(null);
      } catch (Throwable e) {
        done.completeExceptionally(e);
      }
    }, name);
    thread.setDaemon(true);
    return thread;
  }

  /** Waits (bounded) until {@code thread} waits or {@code done} completes. */
  /**
   * Closes {@code closeable} from two threads while its writer thread is held in {@code output}:
   * the first close waits, the second waits too (it does not return while the first finishes the
   * file); once released, the file holds the one message of {@code topic}.
   */
  private static void closeTwiceWhileHeld(AutoCloseable closeable, StallingOutput output, Path file, String topic)
      throws Exception {
    CompletableFuture<Void> firstDone = new CompletableFuture<>();
    Thread first = closer(closeable, firstDone, "first closer");
    first.start();
    awaitWaitingOrDone(first, firstDone);
    assertFalse(firstDone.isDone(), "the first close waits for the held writer thread");

    CompletableFuture<Void> secondDone = new CompletableFuture<>();
    Thread second = closer(closeable, secondDone, "second closer");
    second.start();
    awaitWaitingOrDone(second, secondDone);
    boolean secondReturnedWhileWriting = secondDone.isDone();

    output.release();
    firstDone.get(30, TimeUnit.SECONDS);
    secondDone.get(30, TimeUnit.SECONDS);
    assertFalse(secondReturnedWhileWriting,
        "the second close() returned while the first was still finishing the file");
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount(topic));
    }
  }

  private static void awaitWaitingOrDone(Thread thread, CompletableFuture<Void> done) {
    long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30);
    while (!done.isDone() && !WAITING.contains(thread.getState())) {
      if (System.nanoTime() > deadline) {
        fail(thread.getName() + " neither waited nor returned within 30 s: " + thread.getState()
            + (thread.getState() == Thread.State.RUNNABLE ? " (spinning)" : ""));
      }
      Thread.onSpinWait();
    }
  }

  @Test
  void aSecondConcurrentCloseReturnsOnlyOnceTheFileIsFinished() throws Exception {
    Path file = dir.resolve("closing.mcap");
    StallingOutput[] output = new StallingOutput[1];
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(1).queue(100, 1 << 20),
        path -> output[0] = new StallingOutput(path));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    output[0].stall();
    assertTrue(samples.write(1, 1, 1, new Sample(1)));
    assertTrue(output[0].awaitBlocked(30), "the writer thread is held writing the chunk");

    closeTwiceWhileHeld(writer, output[0], file, "samples");
  }

  /** {@link McapRecorder#close()} likewise: it closes its writer. */
  @Test
  void aSecondConcurrentRecorderCloseReturnsOnlyOnceTheFileIsFinished() throws Exception {
    Path file = dir.resolve("recording.mcap");
    StallingOutput[] output = new StallingOutput[1];
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(4)).build())) {
      EventBlock<Integer> ticks = new EventBlock<>();
      core.source("ticks", ticks);
      core.start();
      McapRecorder recorder = RecordingMcap.stream(core.recording(), file,
          McapWriterOptions.defaults().chunkSize(1).queue(100, 1 << 20), Map.of(), Map.of(),
          path -> output[0] = new StallingOutput(path));
      output[0].stall();
      ticks.publish(1);
      assertTrue(output[0].awaitBlocked(30), "the writer thread is held writing the chunk");

      closeTwiceWhileHeld(recorder, output[0], file, "ticks");
    }
  }

  /**
   * A synchronous writer's close while a write waits for a stalled disk waits for it blocked, not
   * spinning a core until the disk comes back, and then finishes the file with that message.
   */
  @Test
  void aSynchronousCloseWaitsForAWriteUnderWayWithoutSpinning() throws Exception {
    Path file = dir.resolve("synchronous.mcap");
    StallingOutput[] output = new StallingOutput[1];
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(1).synchronous(),
        path -> output[0] = new StallingOutput(path));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    output[0].stall();
    CompletableFuture<Boolean> written = CompletableFuture.supplyAsync(() -> samples.write(1, 1, 1, new Sample(1)));
    try {
      assertTrue(output[0].awaitBlocked(30), "the write waits for the disk");
      CompletableFuture<Void> closed = new CompletableFuture<>();
      Thread closing = closer(writer, closed, "closer");
      closing.start();
      awaitWaitingOrDone(closing, closed);
      assertFalse(closed.isDone(), "close() waits for the write under way");
      output[0].release();
      assertTrue(written.get(30, TimeUnit.SECONDS));
      closed.get(30, TimeUnit.SECONDS);
    } finally {
      output[0].release();
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount("samples"));
    }
  }
}
