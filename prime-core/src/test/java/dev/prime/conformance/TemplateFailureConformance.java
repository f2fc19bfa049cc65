package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Repeat;
import dev.prime.Source;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.function.Function;
import org.junit.jupiter.api.Test;

/**
 * A block that fails inside a template is named like one that fails in a linked chain
 * (architecture, <i>Errors</i>: a synchronous caller gets "{@code ChainFailedException} naming the
 * chain as you named it (the innermost chain of a linked chain)", its cause the block's own
 * throwable; a service's failure goes to the {@code ErrorHandler} "together with the name of the
 * chain that failed" and the block's own throwable, and the service goes on), for every template
 * that takes a chain.
 */
public interface TemplateFailureConformance extends ConformanceBase {

  /** The templates, each made around {@code bad}: name to template. */
  private static Map<String, Function<Chain<Integer, Integer>, Chain<Integer, ?>>> templates(
      PrimeCore core) {
    Map<String, Function<Chain<Integer, Integer>, Chain<Integer, ?>>> all = new LinkedHashMap<>();
    all.put("ifThenElse", bad -> core.ifThenElse(x -> x > 0, bad, core.chain((Integer x) -> x)));
    all.put(
        "forEach",
        bad -> core.link(core.chain((Integer x) -> List.of(x)), core.forEach(bad)));
    all.put("union", bad -> core.union(core.chain((Integer x) -> x), bad));
    all.put("guard", bad -> core.guard(x -> true, bad, (Integer x) -> x));
    all.put("fork", bad -> core.fork(bad, new EventBlock<Integer>()));
    all.put("isolate", bad -> core.isolate(bad).newUser());
    all.put(
        "repeater",
        bad -> core.repeater(bad, (Integer input, Integer output, List<Void> c) -> Repeat.stop(output)));
    return all;
  }

  /**
   * A block failing inside a template called synchronously: {@link ChainFailedException} naming
   * the failing chain, with the block's own exception as its cause, on every template; the chain
   * goes on working.
   */
  @Test
  default void aBlockFailingInsideATemplateIsNamedToItsCaller() {
    try (PrimeCore core = newCore()) {
      Map<String, Block<Integer, ?>> blocks = new LinkedHashMap<>();
      Map<String, RuntimeException> booms = new LinkedHashMap<>();
      for (var template : templates(core).entrySet()) {
        String name = "bad-" + template.getKey();
        RuntimeException boom = new IllegalStateException("boom in " + name);
        booms.put(name, boom);
        Chain<Integer, Integer> bad =
            core.chain(
                name,
                (Integer x) -> {
                  if (x < 100) {
                    throw boom;
                  }
                  return x;
                });
        blocks.put(name, template.getValue().apply(bad).toBlock());
      }
      core.start();
      List<String> wrong = new ArrayList<>();
      for (var entry : blocks.entrySet()) {
        String name = entry.getKey();
        try {
          entry.getValue().process(1);
          wrong.add(name + ": no failure");
        } catch (ChainFailedException e) {
          if (!name.equals(e.chainName())) {
            wrong.add(name + ": named '" + e.chainName() + "'");
          }
          if (e.getCause() == null
              || !booms.get(name).getMessage().equals(e.getCause().getMessage())
              || e.getCause().getClass() != IllegalStateException.class) {
            wrong.add(name + ": cause " + e.getCause());
          }
        } catch (RuntimeException e) {
          wrong.add(name + ": threw " + e);
        }
        try {
          entry.getValue().process(100);
        } catch (RuntimeException e) {
          wrong.add(name + ": the next call threw " + e);
        }
      }
      assertEquals(List.of(), wrong);
    }
  }

  /**
   * A block failing inside a template that runs as a service on a source: the error handler gets
   * the failing chain's name and the block's own exception, and the service goes on with the next
   * value, on every template.
   */
  @Test
  default void aBlockFailingInsideATemplateOnASourceIsReportedUnderItsName()
      throws InterruptedException {
    Map<String, String> reported = new ConcurrentHashMap<>();
    Map<String, Throwable> errors = new ConcurrentHashMap<>();
    List<String> names = new ArrayList<>();
    CountDownLatch failures = new CountDownLatch(7);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  reported.put(error.getMessage(), service);
                  errors.put(error.getMessage(), error);
                  failures.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("numbers", events);
      List<dev.prime.Reader<?>> outputs = new ArrayList<>();
      for (var template : templates(core).entrySet()) {
        String name = "bad-" + template.getKey();
        names.add(name);
        Chain<Integer, Integer> bad =
            core.chain(
                name,
                (Integer x) -> {
                  if (x < 100) {
                    throw new IllegalStateException("boom in " + name);
                  }
                  return x;
                });
        outputs.add(core.link(source, template.getValue().apply(bad)).reader());
      }
      core.start();
      events.publish(1);
      events.publish(100);
      for (dev.prime.Reader<?> output : outputs) {
        takeOrFail(output); // the service went on: 100 came out of every template
      }
      assertTrue(failures.await(patience().toMillis(), TimeUnit.MILLISECONDS), "reported: " + reported);
      List<String> wrong = new ArrayList<>();
      for (String name : names) {
        String service = reported.get("boom in " + name);
        if (!name.equals(service)) {
          wrong.add(name + " reported as '" + service + "'");
        }
        Throwable error = errors.get("boom in " + name);
        if (error == null || error.getClass() != IllegalStateException.class) {
          wrong.add(name + ": the handler got " + error);
        }
      }
      assertEquals(List.of(), wrong, "reported: " + reported);
    }
  }
}
