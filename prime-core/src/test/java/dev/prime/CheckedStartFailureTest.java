package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.conformance.ConformanceBase;
import dev.prime.spi.GenericChainCompiler;
import java.io.IOException;
import org.junit.jupiter.api.Test;

/**
 * A media's onStart() written in a language without checked exceptions (Kotlin) can throw a
 * checked one: the core must fail to start as for any other exception, not stay started.
 */
class CheckedStartFailureTest {

  private static final IOException FAILURE = new IOException("no route to the store");

  /** A core whose onStart() throws a checked exception, as Kotlin code may. */
  private static final class CheckedFailingCore extends PrimeCore {
    CheckedFailingCore() {
      super("checked-failing", CoreConfig.defaults());
    }

    @Override
    protected ChainCompiler<?> chainCompiler() {
      return new GenericChainCompiler();
    }

    @Override
    protected void onStart() {
      CheckedStartFailureTest.<RuntimeException>sneakyThrow(FAILURE);
    }
  }

  @SuppressWarnings("unchecked")
  private static <T extends Throwable> void sneakyThrow(Throwable t) throws T {
    throw (T) t;
  }

  @Test
  void aCheckedExceptionFromOnStartFailsTheStart() throws Exception {
    try (CheckedFailingCore core = new CheckedFailingCore()) {
      core.link(core.source(new EventBlock<Integer>()), core.chain(x -> x));
      Throwable thrown = assertThrows(Throwable.class, core::start);
      assertSame(FAILURE, thrown, "start() throws what onStart() threw");
      IllegalStateException again = assertThrows(IllegalStateException.class, core::start);
      assertTrue(
          again.getMessage().contains("failed to start"),
          "a second start() says the first failed: " + again.getMessage());
      assertSame(FAILURE, again.getCause(), "the refusal quotes the start's failure");
      IllegalStateException declared =
          assertThrows(
              IllegalStateException.class, () -> core.chain((Integer x) -> x),
              "a declaration after a failed start is refused");
      assertTrue(
          declared.getMessage().contains("failed to start"),
          "the refusal says the start failed: " + declared.getMessage());
      assertEquals(
          java.util.List.of(), ConformanceBase.threadsOf(core), "services started after a failed start");
    }
  }
}
