package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTimeoutPreemptively;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.nio.file.Path;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * The background writer's bounded queue: a stalled disk never stalls the caller; what does not
 * fit is dropped, counted exactly, and reported in the file.
 */
class BoundedQueueTest {
  @TempDir Path dir;

  record Sample(int index, String padding) {}

  private StallingOutput output;

  private McapWriter open(Path file, McapWriterOptions options) throws IOException {
    return McapWriter.open(file, options, path -> output = new StallingOutput(path));
  }

  @Test
  void aStalledDiskDropsExactlyWhatDoesNotFitInTheQueueAndTheFileSaysSo() throws Exception {
    Path file = dir.resolve("stalled.mcap");
    int capacity = 50;
    int extra = 37;
    // chunk size 1: every message is a chunk of its own, written (and so stalled) at once
    McapWriter writer = open(file, McapWriterOptions.defaults().chunkSize(1).queue(capacity, 1 << 30));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    McapChannel<Sample> other = writer.channel("other", Sample.class);
    output.stall();
    assertTrue(samples.write(0, 0, 0, new Sample(0, "")));
    assertTrue(output.awaitBlocked(30), "the writer thread reached the stalled disk");
    // the writer thread holds message 0 in its stalled write; the queue is empty
    List<Boolean> accepted = assertTimeoutPreemptively(Duration.ofSeconds(30), () -> {
      List<Boolean> results = new ArrayList<>();
      for (int i = 1; i <= capacity + extra; i++) {
        McapChannel<Sample> channel = i % 2 == 0 ? samples : other;
        results.add(channel.write(i, i, i, new Sample(i, "")));
      }
      return results;
    }, "writes must not wait for a stalled disk");
    for (int i = 0; i < capacity; i++) {
      assertTrue(accepted.get(i), "write " + (i + 1) + " fits in the queue");
    }
    for (int i = capacity; i < capacity + extra; i++) {
      assertFalse(accepted.get(i), "write " + (i + 1) + " finds the queue full");
    }
    assertEquals(extra, writer.droppedCount());
    long droppedOther = countOdd(capacity + 1, capacity + extra);
    assertEquals(droppedOther, other.droppedCount());
    assertEquals(extra - droppedOther, samples.droppedCount());

    output.release();
    writer.close();
    assertEquals(extra, writer.droppedCount());

    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1 + capacity, reader.statistics().messageCount());
      List<Long> sequences = reader.messages().map(McapMessage::sequence).collect(Collectors.toList());
      List<Long> expected = new ArrayList<>();
      for (long i = 0; i <= capacity; i++) {
        expected.add(i);
      }
      assertEquals(expected, sequences, "the first messages are kept, in order; the overflow is what is lost");
      List<Map<String, String>> loss = reader.metadata(McapWriter.LOSS_METADATA);
      assertEquals(1, loss.size());
      assertEquals(String.valueOf(extra), loss.get(0).get("dropped_messages"));
      assertEquals(String.valueOf(droppedOther), loss.get(0).get("dropped.other"));
      assertEquals(String.valueOf(extra - droppedOther), loss.get(0).get("dropped.samples"));
    }
  }

  private static long countOdd(int from, int to) {
    long n = 0;
    for (int i = from; i <= to; i++) {
      if (i % 2 != 0) {
        n++;
      }
    }
    return n;
  }

  @Test
  void theByteBoundDropsToo() throws Exception {
    Path file = dir.resolve("bytes.mcap");
    Sample big = new Sample(1, "x".repeat(1000));
    int size = ValueType.of(Sample.class).toJson(big).length;
    int fit = 5;
    McapWriter writer = open(file, McapWriterOptions.defaults().chunkSize(1).queue(10_000, (long) size * fit));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    output.stall();
    assertTrue(samples.write(0, 0, 0, big));
    assertTrue(output.awaitBlocked(30));
    int accepted = 0;
    for (int i = 1; i <= 20; i++) {
      if (samples.write(i, i, i, big)) {
        accepted++;
      }
    }
    assertEquals(fit, accepted, "the queue holds " + fit + " messages of " + size + " bytes");
    assertEquals(20 - fit, writer.droppedCount());
    output.release();
    writer.close();
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1 + fit, reader.messageCount("samples"));
    }
  }

  /**
   * A message larger than the queue's byte bound could never be queued, not even on an empty
   * queue: it is refused with an {@link IllegalArgumentException} naming its size, the bound and
   * how to raise it, not dropped and counted as if the queue were full. The queue is untouched:
   * nothing counts as dropped, and the next message that fits is written.
   */
  @Test
  void aMessageLargerThanTheByteBoundIsRefusedSayingSo() throws Exception {
    Path file = dir.resolve("too-large.mcap");
    Sample big = new Sample(1, "x".repeat(2000));
    int size = ValueType.of(Sample.class).toJson(big).length;
    long bound = 1024;
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().queue(100, bound));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    IllegalArgumentException e =
        assertThrows(IllegalArgumentException.class, () -> samples.write(1, 1, 1, big));
    assertTrue(e.getMessage().contains(size + " bytes"), e.getMessage());
    assertTrue(e.getMessage().contains("byte bound of " + bound), e.getMessage());
    assertTrue(e.getMessage().contains("'samples'"), e.getMessage());
    assertTrue(e.getMessage().contains("McapWriterOptions.queue"), e.getMessage());
    assertEquals(0, writer.droppedCount(), "the queue was not full: nothing was dropped");
    assertEquals(0, samples.droppedCount());
    assertTrue(samples.write(2, 2, 2, new Sample(2, "")), "a message that fits is written");
    writer.close();
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount("samples"));
      assertEquals("0", reader.metadata(McapWriter.LOSS_METADATA).get(0).get("dropped_messages"));
    }
  }

  /**
   * {@link McapWriterOptions#queue(int, long)} takes any positive bound in messages, and the
   * writer's memory is bounded by the byte bound ({@link McapWriter}'s design note): a message
   * bound as large as an int holds is a queue bounded in bytes only.
   */
  @Test
  void aMessageBoundAsLargeAsAnIntIsAQueueBoundedInBytes() throws Exception {
    Path file = dir.resolve("bytes-only.mcap");
    try (McapWriter writer =
        McapWriter.open(file, McapWriterOptions.defaults().queue(Integer.MAX_VALUE, 1 << 20))) {
      McapChannel<Sample> samples = writer.channel("samples", Sample.class);
      for (int i = 0; i < 100; i++) {
        assertTrue(samples.write(i, i, i, new Sample(i, "")), "write " + i);
      }
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(100, reader.messageCount("samples"));
    }
  }

  @Test
  void concurrentWritersLoseNothingUnaccounted() throws Exception {
    Path file = dir.resolve("concurrent.mcap");
    int threads = 4;
    int perThread = 5_000;
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(8192).queue(256, 1 << 20));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    AtomicLong accepted = new AtomicLong();
    CountDownLatch start = new CountDownLatch(1);
    CountDownLatch done = new CountDownLatch(threads);
    for (int t = 0; t < threads; t++) {
      int thread = t;
      new Thread(() -> {
        try {
          start.await();
          for (int i = 0; i < perThread; i++) {
            if (samples.write(i, i, thread, new Sample(i, "t" + thread))) {
              accepted.incrementAndGet();
            }
          }
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
        } finally {
          done.countDown();
        }
      }).start();
    }
    start.countDown();
    assertTrue(done.await(60, TimeUnit.SECONDS));
    writer.close();
    assertEquals(threads * perThread, accepted.get() + writer.droppedCount());
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(accepted.get(), reader.messageCount("samples"));
      assertEquals(accepted.get(), reader.messages().count());
      assertEquals(String.valueOf(writer.droppedCount()),
          reader.metadata(McapWriter.LOSS_METADATA).get(0).get("dropped_messages"));
    }
  }

  @Test
  void aFailingDiskIsReportedByCloseAndLaterMessagesCountAsDropped() throws Exception {
    Path file = dir.resolve("failing.mcap");
    McapWriter writer = open(file, McapWriterOptions.defaults().chunkSize(1).queue(100, 1 << 20));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    output.fail();
    for (int i = 0; i < 10; i++) {
      samples.write(i, i, i, new Sample(i, ""));
    }
    IOException e = assertThrows(IOException.class, writer::close);
    assertTrue(e.getMessage().contains("writing MCAP file " + file + " failed: No space left on device"), e.getMessage());
    assertEquals(10, writer.droppedCount(), "every message after the failure is counted as lost");
    assertThrows(IllegalStateException.class, () -> samples.write(11, 11, 11, new Sample(11, "")));
  }

  @Test
  void anUncheckedFailureInTheWriterThreadNeitherHangsCloseNorGoesUnreported() throws Exception {
    Path file = dir.resolve("bug.mcap");
    McapWriter writer = open(file, McapWriterOptions.defaults().chunkSize(1).queue(10, 1 << 20));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    output.failWith(new IllegalStateException("a bug below the writer"));
    int accepted = 0;
    for (int i = 0; i < 300; i++) {
      if (samples.write(i, i, i, new Sample(i, ""))) {
        accepted++;
      }
    }
    IOException e = assertTimeoutPreemptively(Duration.ofSeconds(30), () -> assertThrows(IOException.class, writer::close));
    assertTrue(e.getMessage().contains("the MCAP writer thread failed: java.lang.IllegalStateException: a bug below the writer"),
        e.getMessage());
    assertTrue(accepted >= 1, "the first write finds the queue empty");
    assertEquals(300, writer.droppedCount(),
        "the writes refused by the full queue, the one that met the failure and every one after it");
    assertEquals(300, samples.droppedCount());
  }

  @Test
  void synchronousWritesNeverDropAndWriteInTheCallersThread() throws Exception {
    Path file = dir.resolve("sync.mcap");
    McapWriter writer = open(file, McapWriterOptions.defaults().synchronous().chunkSize(1));
    McapChannel<Sample> samples = writer.channel("samples", Sample.class);
    output.fail();
    // the caller sees the disk's failure at once
    assertThrows(java.io.UncheckedIOException.class, () -> samples.write(0, 0, 0, new Sample(0, "")));
    assertThrows(IOException.class, writer::close);

    Path ok = dir.resolve("sync-ok.mcap");
    try (McapWriter w = McapWriter.open(ok, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Sample> s = w.channel("samples", Sample.class);
      for (int i = 0; i < 1000; i++) {
        assertTrue(s.write(i, i, i, new Sample(i, "")));
      }
    }
    try (McapReader reader = McapReader.open(ok)) {
      assertEquals(1000, reader.messageCount("samples"));
    }
  }
}
