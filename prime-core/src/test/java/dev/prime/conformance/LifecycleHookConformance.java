package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.util.List;
import java.util.concurrent.CopyOnWriteArrayList;
import org.junit.jupiter.api.Test;

/** {@link PrimeCore#whenRunning}: work beside the diagram started and stopped with the core. */
public interface LifecycleHookConformance extends ConformanceBase {

  @Test
  default void aHookStartsWithTheCoreCanPublishThenAndClosesOnceWithIt() throws InterruptedException {
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore();
    try (core) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.source("fed", events).reader();
      core.whenRunning(
          "feeder",
          () -> {
            calls.add("start");
            events.publish(7); // the core counts as started: a media that refuses early publishes accepts it
          },
          () -> calls.add("close"));
      assertEquals(List.of(), calls, "nothing runs before start()");
      core.start();
      assertEquals(List.of("start"), calls);
      assertEquals(7, takeOrFail(reader));
      List<String> late = new CopyOnWriteArrayList<>();
      core.whenRunning("late", () -> late.add(Thread.currentThread().getName()), () -> late.add("close"));
      assertEquals(List.of(Thread.currentThread().getName()), late, "a hook added to a started core starts at once, here");
      core.close();
      core.close();
      assertEquals(List.of("start", "close"), calls);
      assertEquals(2, late.size());
    }
    assertThrows(CoreClosedException.class, () -> core.whenRunning("after", () -> {}, () -> {}));
  }

  @Test
  default void aHookOfACoreNeverStartedOnlyCloses() {
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore();
    core.whenRunning("feeder", () -> calls.add("start"), () -> calls.add("close"));
    core.close();
    assertEquals(List.of("close"), calls);
  }

  @Test
  default void aHookThatThrowsGoesToTheErrorHandlerAndStartCarriesOn() throws InterruptedException {
    List<Object[]> failures = new CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler((service, input, error) -> failures.add(new Object[] {service, input, error}))
            .build();
    IllegalStateException boom = new IllegalStateException("boom");
    List<String> calls = new CopyOnWriteArrayList<>();
    try (PrimeCore core = newCore(config)) {
      core.whenRunning("broken", () -> { throw boom; }, () -> calls.add("broken closed"));
      core.whenRunning("fine", () -> calls.add("fine started"), () -> {});
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.link(core.source(events), core.chain((Integer x) -> x + 1)).reader();
      core.start();
      events.publish(1);
      assertEquals(2, takeOrFail(reader));
      assertEquals(List.of("fine started"), calls);
      assertEquals(1, failures.size());
      assertEquals("broken", failures.get(0)[0]);
      assertEquals("start", failures.get(0)[1]);
      assertSame(boom, failures.get(0)[2]);
    }
    assertEquals(List.of("fine started", "broken closed"), calls);
  }
}
