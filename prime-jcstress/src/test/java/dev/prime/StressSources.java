package dev.prime;

import dev.prime.ChainCompiler;
import dev.prime.spi.GenericChainCompiler;
import java.time.Duration;

/**
 * The in-memory sources the jcstress tests race on. jcstress makes millions of test states, so
 * they share one core (a source uses its core only for its name and its publish timeout); each
 * state gets a source of its own. The tests live in {@code dev.prime} because {@link
 * MemorySource} is package-private.
 */
final class StressSources {
  /** Longest bounded wait in a test: far beyond any real hand-off, so reaching it is a failure. */
  static final Duration BOUND = Duration.ofSeconds(10);

  /** The smallest core a source can belong to; it is never started, its chains never used. */
  private static final class BareCore extends PrimeCore {
    BareCore() {
      super("jcstress", CoreConfig.builder().publishTimeout(BOUND).build());
    }

    @Override
    protected ChainCompiler<?> chainCompiler() {
      return new GenericChainCompiler();
    }
  }

  private static final PrimeCore CORE = new BareCore();

  private StressSources() {}

  /**
   * A bounded take, as a number (jcstress actors throw no checked exceptions).
   *
   * @return the value taken; 0 if none came within {@link #BOUND}; -8 if one came only when the
   *     deadline was reached (the take re-reads then, so a lost wake-up would otherwise pass
   *     unseen); -1 if the source closed; -9 if the taking thread was interrupted
   */
  static int take(Reader<Integer> reader) {
    long start = System.nanoTime();
    try {
      int value = reader.take(BOUND).orElse(0);
      return System.nanoTime() - start >= BOUND.toNanos() ? -8 : value;
    } catch (CoreClosedException e) {
      return -1;
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      return -9;
    }
  }

  /** {@return a new in-memory source of the shared core keeping {@code retention} values} */
  static MemorySource<Integer> source(int retention) {
    return new MemorySource<>(CORE, "stress", retention);
  }

  /**
   * {@return a new in-memory source like {@link #source(int)} whose readers neither spin nor
   * yield: one with nothing to read goes straight to the sleeper list and parks, so the race
   * between parking and a publish or close is hit in most samples, not only when the standard
   * waiting budget (microseconds) runs out}
   */
  static MemorySource<Integer> parkingSource(int retention) {
    return new MemorySource<>(CORE, "stress", retention, null, () -> {}, 0, 0);
  }
}
