package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.EventBlock;
import dev.prime.Tuple2;
import dev.prime.radiant.internal.FusedCompiler;
import java.lang.reflect.Field;
import java.lang.reflect.Method;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.Callable;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.FutureTask;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.Test;

/**
 * Chains far longer than a method may hold: they compile without recursion over the chain, run
 * on a thread with the default stack, and fail under the right name. Every test builds and runs
 * its chain on a fresh thread of the JVM's default stack size (not JUnit's main thread, whose
 * stack the launcher may size differently).
 */
class LongChainTest {
  private static final int LINKS = 100_000;
  private static final int NESTING = 10_000;
  private static final String FUSED_PACKAGE = "dev.prime.radiant.fused.";

  private final RadiantCore core = new RadiantCore();

  @AfterEach
  void close() {
    core.close();
  }

  /** Adds a number; public, so fused classes call it by its own type. */
  public static final class Add implements Block<Long, Long> {
    private final long n;

    Add(long n) {
      this.n = n;
    }

    @Override
    public Long process(Long x) {
      return x + n;
    }
  }

  /** Counts the frames of fused classes on the stack where it runs; passes its input on. */
  static final class FusedDepth implements Block<Long, Long> {
    final AtomicInteger deepest = new AtomicInteger();

    @Override
    public Long process(Long x) {
      int depth =
          StackWalker.getInstance()
              .walk(
                  frames ->
                      (int)
                          frames
                              .filter(f -> f.getClassName().startsWith(FUSED_PACKAGE))
                              .count());
      deepest.accumulateAndGet(depth, Math::max);
      return x;
    }
  }

  /** Runs {@code work} on a new thread with the default stack size; bounded in time. */
  static <T> T onDefaultStack(Callable<T> work) throws Exception {
    FutureTask<T> task = new FutureTask<>(work);
    Thread thread = new Thread(task, "default-stack");
    thread.start();
    try {
      return task.get(300, TimeUnit.SECONDS);
    } catch (ExecutionException e) {
      if (e.getCause() instanceof Exception failure) {
        throw failure;
      }
      throw new AssertionError("the chain failed on the default stack", e.getCause());
    } finally {
      thread.interrupt();
      thread.join(10_000);
    }
  }

  @Test
  void aChainOfOneHundredThousandLinksBuildsAndRuns() throws Exception {
    FusedDepth depth = new FusedDepth();
    long before = FusedCompiler.classesGenerated();
    Block<Long, Long> block =
        onDefaultStack(
            () -> {
              Chain<Long, Long> chain = core.chain(new Add(1));
              for (int i = 2; i <= LINKS; i++) {
                chain = chain.then(i == LINKS / 2 ? depth : new Add(i));
              }
              return chain.toBlock();
            });
    long classes = FusedCompiler.classesGenerated() - before;
    int segments = (LINKS + FusedCompiler.MAX_SITES - 1) / FusedCompiler.MAX_SITES; // 500
    int groups = (segments + FusedCompiler.MAX_SITES - 1) / FusedCompiler.MAX_SITES; // 3
    assertEquals(
        segments + groups + 1,
        classes,
        "classes for " + LINKS + " links: " + segments + " segments of "
            + FusedCompiler.MAX_SITES + " blocks, " + groups + " group drivers and a driver");

    long sum = (long) LINKS * (LINKS + 1) / 2 - LINKS / 2;
    assertEquals(sum + 7, onDefaultStack(() -> block.process(7L)));
    assertEquals(sum - 3, onDefaultStack(() -> block.process(-3L)));
    assertEquals(
        3,
        depth.deepest.get(),
        "fused frames on the stack in the middle of the chain: the driver, a group driver and a"
            + " segment, never a frame per link");
  }

  @Test
  void aDriverCallsItsSegmentsByTheirOwnClasses() throws Exception {
    Block<Long, Long> block =
        onDefaultStack(
            () -> {
              Chain<Long, Long> chain = core.chain(new Add(1));
              for (int i = 2; i <= FusedCompiler.MAX_SITES * 3; i++) {
                chain = chain.then(new Add(1));
              }
              return chain.toBlock();
            });
    assertEquals(FusedCompiler.MAX_SITES * 3L, block.process(0L));
    Field[] fields = block.getClass().getDeclaredFields();
    assertEquals(3, fields.length, "one field per segment");
    for (Field field : fields) {
      Class<?> segment = field.getType();
      assertTrue(segment.getName().startsWith(FUSED_PACKAGE + "Fused_"), segment.getName());
      assertSame(
          block.getClass().getClassLoader(),
          segment.getClassLoader(),
          "a chain's classes share its loader");
      field.setAccessible(true);
      assertTrue(field.get(null).toString().startsWith("part of fused Radiant chain"));
    }
    assertTrue(block.toString().startsWith("fused Radiant chain"), block.toString());
  }

  @Test
  void aFailingBlockInTheMiddleOfALongChainIsReportedUnderItsOwnChain() throws Exception {
    Block<Long, Long> block =
        onDefaultStack(
            () -> {
              Chain<Long, Long> chain = core.chain(new Add(1));
              for (int i = 2; i <= LINKS; i++) {
                chain =
                    i == LINKS / 2 + 13
                        ? chain.then(
                            core.chain(
                                "middle",
                                (Long x) -> {
                                  if (x < 0) {
                                    throw new IllegalStateException("sensor unplugged " + x);
                                  }
                                  return x;
                                }))
                        : chain.then(new Add(0));
              }
              return chain.toBlock();
            });
    assertEquals(42L + 1, onDefaultStack(() -> block.process(42L)));
    ChainFailedException e =
        assertThrows(ChainFailedException.class, () -> onDefaultStack(() -> block.process(-5L)));
    assertEquals("middle", e.chainName());
    assertEquals(IllegalStateException.class, e.getCause().getClass());
    assertEquals("sensor unplugged -4", e.getCause().getMessage(), "the block saw its own input");
    StackTraceElement[] trace = e.getCause().getStackTrace();
    assertTrue(trace[0].getClassName().startsWith(LongChainTest.class.getName()), trace[0] + "");
    assertTrue(
        trace[1].getClassName().startsWith(FUSED_PACKAGE) && trace[1].getMethodName()
            .equals("process"),
        "the failing block is called directly by a fused segment: " + trace[1]);
  }

  @Test
  void tenThousandNestedGuardsCompileRunAndNameTheirFailures() throws Exception {
    FusedDepth depth = new FusedDepth();
    Block<Long, Long> block =
        onDefaultStack(
            () -> {
              Chain<Long, Long> chain = core.chain(depth);
              for (int i = 1; i <= NESTING; i++) {
                Chain<Long, Long> body = chain.then(new Add(1));
                if (i == NESTING / 2) {
                  body =
                      body.then(
                          core.chain(
                              "deep",
                              (Long x) -> {
                                if (x == 1_000_000L + NESTING / 2) {
                                  throw new IllegalArgumentException("deep failure");
                                }
                                return x;
                              }));
                }
                chain = core.guard((Long x) -> x >= 0, body, (Long x) -> Long.MIN_VALUE);
              }
              return chain.toBlock();
            });
    assertEquals(5L + NESTING, onDefaultStack(() -> block.process(5L)));
    assertEquals(Long.MIN_VALUE, onDefaultStack(() -> block.process(-1L)));
    ChainFailedException e =
        assertThrows(
            ChainFailedException.class, () -> onDefaultStack(() -> block.process(1_000_000L)));
    assertEquals("deep", e.chainName());
    assertEquals("deep failure", e.getCause().getMessage());
    // nesting is real nesting: one fused class per piece of it, each piece many levels deep
    int deepest = depth.deepest.get();
    assertTrue(
        deepest >= 100 && deepest <= 200, // about 150: one per 200 call sites of nesting
        "fused frames at the innermost of " + NESTING + " nested guards: " + deepest);
  }

  /**
   * "Nests of 10,000 templates compile and run on a default thread stack", for the templates
   * the guard and if/else tests leave out: 10,000 nested for-each loops, unions and forks.
   */
  @Test
  @SuppressWarnings({"unchecked", "rawtypes"})
  void tenThousandNestedForEachesUnionsAndForksCompileAndRun() throws Exception {
    AtomicInteger published = new AtomicInteger();
    EventBlock<Long> events = new EventBlock<>();
    events.subscribe(x -> published.incrementAndGet());
    Block[] blocks =
        onDefaultStack(
            () -> {
              Chain loops = core.chain(new Add(1));
              Chain unions = core.chain(new Add(1));
              Chain<Long, Long> forks = core.chain(new Add(0));
              for (int i = 0; i < NESTING; i++) {
                loops = core.forEach(loops);
                unions = core.union(unions, core.chain(new Add(i)));
                forks = core.fork(forks.then(new Add(1)), events);
              }
              return new Block[] {loops.toBlock(), unions.toBlock(), forks.toBlock()};
            });

    Object nested = List.of(5L);
    for (int i = 1; i < NESTING; i++) {
      nested = List.of(nested);
    }
    Object input = nested;
    Object loops = onDefaultStack(() -> blocks[0].process(input));
    for (int i = 0; i < NESTING; i++) {
      loops = ((List<Object>) loops).get(0);
    }
    assertEquals(6L, loops, "the innermost body ran on the innermost element");

    Object unions = onDefaultStack(() -> blocks[1].process(5L));
    for (int i = NESTING - 1; i >= 0; i--) {
      assertEquals(5L + i, ((Tuple2) unions).second(), "the second part of level " + i);
      unions = ((Tuple2) unions).first();
    }
    assertEquals(6L, unions, "the innermost chain");

    assertEquals((long) NESTING, onDefaultStack(() -> blocks[2].process(0L)));
    assertEquals(NESTING, published.get(), "every fork published its output");
  }

  @Test
  void tenThousandNestedIfsCompileAndRun() throws Exception {
    Block<Long, Long> block =
        onDefaultStack(
            () -> {
              Chain<Long, Long> chain = core.chain(new Add(0));
              for (int i = 1; i <= NESTING; i++) {
                long level = i;
                chain =
                    core.ifThenElse(
                        (Long x) -> x != level, chain.then(new Add(1)), core.chain(new Add(-1)));
              }
              return chain.toBlock();
            });
    // input 0 passes every level: NESTING additions
    assertEquals((long) NESTING, onDefaultStack(() -> block.process(0L)));
    // input NESTING stops at the outermost level
    assertEquals(NESTING - 1L, onDefaultStack(() -> block.process((long) NESTING)));
    // input 7777 goes 7777 levels deep, takes the else branch there, and gets one added by
    // every level outside it
    assertEquals(7777L - 1 + (NESTING - 7777), onDefaultStack(() -> block.process(7777L)));
  }

  @Test
  void aLongChainOfTemplatesComputesWhatItsBlocksDo() throws Exception {
    int rounds = 5_000; // 4 templates and 7 blocks per round: 55,000 call sites
    Block<Long, Long> block =
        onDefaultStack(
            () -> {
              Chain<Long, Long> chain = core.chain(new Add(0));
              for (int i = 0; i < rounds; i++) {
                chain =
                    chain
                        .then(
                            core.ifThenElse(
                                (Long x) -> x % 2 == 0,
                                core.chain(new Add(1)),
                                core.chain(new Add(3))))
                        .then((Long x) -> List.of(x, 1L))
                        .then(core.forEach(core.chain(new Add(1))))
                        .then((List<Long> xs) -> xs.get(0) + xs.get(1) - 2)
                        .then(core.union(core.chain(new Add(0)), core.chain(new Add(1))))
                        .then((Tuple2<Long, Long> t) -> t.second());
              }
              return chain.toBlock();
            });
    long expected = 0;
    for (int i = 0; i < rounds; i++) {
      expected += (expected % 2 == 0 ? 1 : 3) + 2;
    }
    assertEquals(expected, onDefaultStack(() -> block.process(0L)));
  }

  @Test
  void chainsThatFitOneMethodStayOneClassWithOneProcessMethod() throws Exception {
    List<Integer> lengths = List.of(1, 4, 16, 32, 64, FusedCompiler.MAX_SITES);
    for (int length : lengths) {
      Chain<Long, Long> chain = core.chain(new Add(1));
      for (int i = 2; i <= length; i++) {
        chain = chain.then(new Add(1));
      }
      long before = FusedCompiler.classesGenerated();
      Block<Long, Long> block = chain.toBlock();
      assertEquals(1, FusedCompiler.classesGenerated() - before, "classes for " + length);
      assertEquals((long) length, block.process(0L));
      List<String> methods = new ArrayList<>();
      for (Method m : block.getClass().getDeclaredMethods()) {
        methods.add(m.getName());
      }
      methods.sort(null);
      assertEquals(List.of("process", "toString"), methods);
    }
    Chain<Long, Long> tooLong = core.chain(new Add(1));
    for (int i = 2; i <= FusedCompiler.MAX_SITES + 1; i++) {
      tooLong = tooLong.then(new Add(1));
    }
    long before = FusedCompiler.classesGenerated();
    Block<Long, Long> block = tooLong.toBlock();
    assertEquals(
        2,
        FusedCompiler.classesGenerated() - before,
        "one segment, and a driver that calls it and then the last block");
    assertEquals(FusedCompiler.MAX_SITES + 1L, block.process(0L));
  }
}
