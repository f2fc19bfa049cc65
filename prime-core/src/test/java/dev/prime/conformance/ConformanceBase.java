package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assertions.fail;

import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;

/**
 * Base of the media conformance kit: a media implements {@link #newCore(CoreConfig)} and inherits
 * every semantic test through {@link MediaConformance}.
 *
 * <p>Hooks that media may legitimately override are the default methods without {@code @Test}.
 */
public interface ConformanceBase {

  /** A new, not yet started core of the media under test, built from {@code config}. */
  PrimeCore newCore(CoreConfig config);

  /** A new core with default configuration. */
  default PrimeCore newCore() {
    return newCore(CoreConfig.defaults());
  }

  /**
   * How many service loops linking one chain to a source runs (1 for media that run each
   * source-linked chain as one service thread in this process). Not the topology's services,
   * which are the same on every media ({@link PrimeCore#serviceNames()}).
   */
  default int servicesPerSourceLink() {
    return 1;
  }

  /**
   * How many service loops a chain made by linking {@code chains} chains runs as when it
   * is linked to a source (1 for media that fuse linked chains; Optimus keeps one service per
   * chain and re-routes their lists). It also says what the error handler gets as the input when
   * the second of two linked chains fails: a fused media (1 service for 2 chains) gives the value
   * that entered the linked chain, the others the value that entered the failing chain.
   */
  default int servicesOfLinkedChain(int chains) {
    return servicesPerSourceLink();
  }

  /**
   * A new, not yet started core of the media under test, built from {@code config}, whose
   * services' inputs each hold at most {@code capacity} values a service has not processed: then
   * a publish waits, and after {@link CoreConfig#publishTimeout()} fails with {@link
   * dev.prime.QueueFullException}. By default the source retention, which is that capacity on the
   * in-memory media; a media with a capacity of its own (Optimus: its queue limit) sets that.
   */
  default PrimeCore newCoreWithServiceInputCapacity(CoreConfig config, int capacity) {
    return newCore(config.toBuilder().sourceRetention(capacity).build());
  }
  /**
   * A chain named {@code name} that holds each value until {@code release} opens (at most the
   * patience), counting {@code inside} down as a value enters: on a core made by {@link
   * #newCoreWithServiceInputCapacity}, {@link #fillStuckInput} then fills its service's input.
   */
  default Chain<Integer, Integer> stuckChain(
      PrimeCore core, String name, CountDownLatch inside, CountDownLatch release) {
    return core.chain(
        name,
        (Integer x) -> {
          inside.countDown();
          try {
            release.await(patience().toMillis(), TimeUnit.MILLISECONDS);
          } catch (InterruptedException e) {
            Thread.currentThread().interrupt();
          }
          return x;
        });
  }

  /**
   * Publishes 0, waits until the {@link #stuckChain} holds it, then publishes 1 to {@code
   * capacity}, which fill that chain's service input: the next publish finds it full.
   */
  default void fillStuckInput(EventBlock<Integer> events, CountDownLatch inside, int capacity)
      throws InterruptedException {
    events.publish(0);
    assertTrue(inside.await(patience().toMillis(), TimeUnit.MILLISECONDS), "0 reached the chain");
    for (int i = 1; i <= capacity; i++) {
      events.publish(i);
    }
  }


  /**
   * Whether a synchronous call runs the chain's blocks on the caller's thread (true for the
   * in-memory media). Then a {@link VirtualMachineError} a block throws reaches the caller
   * unchanged and the chain goes on working. A media whose chains are services (Optimus) runs the
   * block on a service's thread: the caller gets the error promptly (unwrapped in the process that
   * ran the block), and the error then ends that service, as it ends any thread; the kit tests
   * each case on the media it applies to.
   */
  default boolean blocksRunOnTheCallersThread() {
    return true;
  }

  /**
   * Whether the thread named {@code name} belongs to the kit's set-up of this media, not to a core
   * (a proxy between the core and its Redis starts a thread per connection): the kit does not hold
   * such a thread to a core's naming. False by default.
   */
  default boolean isFixtureThread(String name) {
    return false;
  }

  /**
   * Whether a publish before {@code start()} waits in the services' inputs until they run (true
   * for the in-memory media). A media that refuses it (Optimus: a publish, a call and a read
   * before {@code start()} fail at once with {@link IllegalStateException}, publishing nothing)
   * returns false, and the kit checks that refusal instead.
   */
  default boolean publishesBeforeStartWait() {
    return true;
  }

  /**
   * The codec the kit gives to {@link CoreConfig.Builder#copyValues}: by default
   * {@link SerializingCodec}, which copies any {@link java.io.Serializable} value and the core's
   * own value types (a timer's ticks, the tuples of a zip or a union, repeats). A media with a
   * codec of its own may return it; Optimus copies through its own codec whatever this is.
   */
  default dev.prime.ValueCodec copyCodec() {
    return SerializingCodec.INSTANCE;
  }

  /**
   * A core whose values cross every service boundary through {@code config}'s {@link
   * CoreConfig#valueCopies() copy codec}: by default {@link #newCore(CoreConfig)}, for the
   * in-memory media copy through it; a media with codecs of its own (Optimus) makes it the core's
   * codec.
   */
  default PrimeCore newCoreWithCodec(CoreConfig config) {
    return newCore(config);
  }

  /** Upper bound for any single wait in the kit; generous because the machine may be busy. */
  default Duration patience() {
    return Duration.ofSeconds(20);
  }

  /** Takes one value from {@code reader}, failing the test instead of hanging. */
  default <T> T takeOrFail(Reader<T> reader) throws InterruptedException {
    Optional<T> value = reader.take(patience());
    if (value.isEmpty()) {
      fail("no value arrived within " + patience());
    }
    return value.get();
  }

  /** Takes {@code count} values from {@code reader}, in order. */
  default <T> List<T> takeOrFail(Reader<T> reader, int count) throws InterruptedException {
    List<T> values = new ArrayList<>(count);
    for (int i = 0; i < count; i++) {
      values.add(takeOrFail(reader));
    }
    return values;
  }

  /** Live threads whose name says they belong to {@code core}. */
  static List<String> threadsOf(PrimeCore core) {
    String prefix = "prime-" + core.name() + "-";
    List<String> names = new ArrayList<>();
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      if (thread.isAlive() && thread.getName().startsWith(prefix)) {
        names.add(thread.getName());
      }
    }
    return names;
  }

  /**
   * Waits, in bounded pauses and at most the patience, until a closed core has no thread left,
   * then asserts it: for a thread that ends only after {@code close()} returned (a block let go).
   */
  default void awaitNoThreadsLeft(PrimeCore core) throws InterruptedException {
    long deadline = System.nanoTime() + patience().toNanos();
    CountDownLatch never = new CountDownLatch(1);
    while (!threadsOf(core).isEmpty() && System.nanoTime() < deadline) {
      never.await(10, TimeUnit.MILLISECONDS); // a bounded pause
    }
    assertNoThreadsLeft(core);
  }

  /** Asserts that a closed core left no thread behind. */
  static void assertNoThreadsLeft(PrimeCore core) {
    assertTrue(core.isClosed(), "close the core before checking its threads");
    assertEquals(List.of(), threadsOf(core), "threads left behind by closed core " + core.name());
  }
}
