package dev.prime.soak;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.lang.ref.Reference;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.stream.Stream;

/**
 * What this JVM holds at one moment, for tests that open and close cores many times and check
 * that nothing is left behind: live threads (all, and those named {@code prime-...}), open file
 * descriptors, child processes and the heap in use after garbage collection.
 *
 * @param threads live threads of the JVM, but the JDK's {@code process reaper} threads (a cached
 *     pool whose idle threads end 60 s after the process they waited for)
 * @param primeThreads names of the live threads whose name starts with {@code prime-}
 * @param fds open file descriptors ({@code /proc/self/fd}), or -1 where there is no such directory
 * @param children command lines of the JVM's live descendant processes
 * @param heapUsed heap bytes in use after {@link #settledHeap()}
 */
public record Footprint(
    int threads, List<String> primeThreads, long fds, List<String> children, long heapUsed) {

  /** Takes a footprint, with the heap settled by {@link #settledHeap()}. */
  public static Footprint take() throws InterruptedException {
    List<String> prime = new ArrayList<>();
    int threads = 0;
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      // the JDK's process reapers are a cached pool: an idle one ends 60 s after its process
      if (thread.isAlive() && !thread.getName().startsWith("process reaper")) {
        threads++;
        if (thread.getName().startsWith("prime-")) {
          prime.add(thread.getName());
        }
      }
    }
    prime.sort(null);
    List<String> children = new ArrayList<>();
    ProcessHandle.current()
        .descendants()
        .filter(ProcessHandle::isAlive)
        .forEach(p -> children.add(p.pid() + " " + p.info().commandLine().orElse("?")));
    return new Footprint(threads, prime, openFds(), children, settledHeap());
  }

  /** Open file descriptors of this process, or -1 where {@code /proc/self/fd} does not exist. */
  public static long openFds() {
    Path fd = Path.of("/proc/self/fd");
    if (!Files.isDirectory(fd)) {
      return -1;
    }
    try (Stream<Path> entries = Files.list(fd)) {
      return entries.count() - 1; // the listing's own descriptor
    } catch (IOException e) {
      return -1;
    }
  }

  /**
   * Heap bytes in use after {@code System.gc()}: the least of up to five collections 50 ms
   * apart, stopping early once two in a row agree within 256 KiB (a collection may leave garbage
   * a later one takes).
   */
  public static long settledHeap() throws InterruptedException {
    Runtime runtime = Runtime.getRuntime();
    CountDownLatch never = new CountDownLatch(1);
    long least = Long.MAX_VALUE;
    long previous = -1;
    for (int i = 0; i < 5; i++) {
      System.gc();
      never.await(50, TimeUnit.MILLISECONDS); // a bounded pause for finalization and cleaners
      long used = runtime.totalMemory() - runtime.freeMemory();
      least = Math.min(least, used);
      if (previous >= 0 && Math.abs(used - previous) < 256 * 1024) {
        break;
      }
      previous = used;
    }
    return least;
  }

  /**
   * Asserts that this footprint, taken after {@code cycles} cycles, holds no more than {@code
   * before} did: at most 2 threads more, no {@code prime-} thread and no child process that was
   * not there before, at most 5 file descriptors more, and heap growth under {@code heapBytes}.
   * Only growth counts: what earlier tests of the same JVM left (a dispatcher's idle threads, a
   * closing connection) may end meanwhile. A leak of one thread, file descriptor or process per
   * cycle breaks these over more than a few cycles.
   */
  public void assertNothingLeftSince(Footprint before, int cycles, long heapBytes) {
    String both = " after " + cycles + " cycles: before " + before + ", after " + this;
    assertTrue(threads - before.threads <= 2, "threads" + both);
    assertEquals(List.of(), added(before.primeThreads, primeThreads), "new prime- threads" + both);
    assertTrue(fds - before.fds <= 5, "open file descriptors" + both);
    assertEquals(List.of(), added(before.children, children), "new child processes" + both);
    assertTrue(heapUsed - before.heapUsed < heapBytes, "heap growth over " + heapBytes + both);
  }

  private static List<String> added(List<String> before, List<String> after) {
    List<String> added = new ArrayList<>(after);
    added.removeAll(before);
    return added;
  }

  /**
   * Asserts that the garbage collector took every closed core but at most one: nothing (a
   * registry, a thread, a listener) keeps a closed core, and with it its blocks and values.
   *
   * @param closed weak references to closed cores
   */
  public static void assertCollected(List<? extends Reference<?>> closed)
      throws InterruptedException {
    settledHeap();
    long kept = closed.stream().filter(reference -> reference.get() != null).count();
    assertTrue(kept <= 1, kept + " of " + closed.size() + " closed cores are still reachable");
  }

  @Override
  public String toString() {
    return "threads="
        + threads
        + " prime-threads="
        + primeThreads
        + " fds="
        + fds
        + " children="
        + children
        + " heapUsed="
        + heapUsed / 1024
        + " KiB";
  }
}
