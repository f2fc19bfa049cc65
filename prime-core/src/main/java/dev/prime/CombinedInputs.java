package dev.prime;

import dev.prime.internal.ServiceThreads;
import java.util.ArrayList;
import java.util.List;
import java.util.function.Consumer;

/**
 * Runs one combinator of several sources ({@link PrimeCore#combineLatest}, {@link PrimeCore#zip},
 * {@link PrimeCore#merge}, {@link Source#withLatestFrom}, the input side of {@link
 * Source#sample}) on the core's own service threads, so every media gets it without media code.
 *
 * <p>Design note. Each input has a reader opened when the combinator is declared (so values
 * published before {@link PrimeCore#start()} wait for it) and a service thread of its own, named
 * {@code <combinator> input <n>} (a space never occurs in a name of the diagram, so these never
 * collide with a service's thread). The thread takes each value and hands it to {@code step}
 * under one lock per combinator: the pairing state is touched by one thread at a time and what
 * it emits is published in the order the values were accepted. A publish that waits (a full
 * service input downstream) holds the lock, so the other inputs wait too: back-pressure, not
 * loss. Failures of a step go to the error handler under the combinator's name, like any
 * service's ({@link SourceService}). A thread runs only if its process hosts the combinator
 * ({@link PrimeCore#isHostedHere}, asked when the thread starts, after {@code start()} decided the
 * hosting): elsewhere it closes its reader and ends at once, so two processes that declare the
 * same diagram never both emit. It asks again for every value: a process that lost the hosting
 * to another (Optimus: its host lease was taken over) stops emitting; the new host reads the
 * inputs through readers of its own.
 */
final class CombinedInputs {
  private CombinedInputs() {}

  /**
   * Opens a reader on every source and then starts (or schedules, before {@code start()}) one
   * service thread per input; if a reader cannot be opened, nothing runs.
   *
   * @param core the core that runs the combinator
   * @param threads its service threads
   * @param name the combinator's name in the diagram
   * @param sources the inputs, in order
   * @param step what to do with value {@code value} of input {@code i}; called under one lock
   */
  static void run(
      PrimeCore core,
      ServiceThreads threads,
      String name,
      List<? extends Source<?>> sources,
      InputStep step) {
    Object lock = new Object();
    List<Reader<?>> readers = openAll(name, sources);
    for (int i = 0; i < sources.size(); i++) {
      int input = i;
      Reader<?> reader = readers.get(i);
      Consumer<Object> accept =
          value -> {
            synchronized (lock) {
              step.accept(input, value);
            }
          };
      String thread = name + " input " + (i + 1);
      // a core closed unstarted holds no publisher of another core up
      threads.add(thread, thread, hostedOnly(core, name, reader, accept), reader::close);
    }
  }

  /**
   * Opens a reader on every input before any thread starts: if one cannot be opened, those opened
   * are closed and nothing runs, so the failed declaration leaves no input thread behind (one would
   * go on feeding the combinator's output, and its name would refuse the declaration made again).
   */
  private static List<Reader<?>> openAll(String name, List<? extends Source<?>> sources) {
    List<Reader<?>> readers = new ArrayList<>(sources.size());
    try {
      for (Source<?> source : sources) {
        readers.add(inputReader(name, source));
      }
    } catch (RuntimeException | Error failed) {
      for (Reader<?> opened : readers) {
        try {
          opened.close();
        } catch (RuntimeException closing) {
          failed.addSuppressed(closing);
        }
      }
      throw failed;
    }
    return readers;
  }

  /**
   * A service loop over {@code reader} that runs only where {@code name} is hosted.
   *
   * @param core the core
   * @param name the service's name in the diagram
   * @param reader its input
   * @param step what it does with each value
   * @return the thread's body
   */
  @SuppressWarnings("unchecked")
  static Runnable hostedOnly(
      PrimeCore core, String name, Reader<?> reader, Consumer<Object> step) {
    SourceService<Object> service =
        new SourceService<>(
            name,
            (Reader<Object>) reader,
            value -> {
              if (core.isHostedHere(name)) { // false once another process took the hosting over
                step.accept(value);
              }
            },
            core.config().errorHandler(),
            core::isClosed);
    return () -> {
      if (!core.isHostedHere(name)) {
        reader.close(); // another process runs it: stop gating or filling this input
        return;
      }
      service.run();
    };
  }

  /**
   * The input of a combinator's service: on an in-memory source a queue that holds publishers up
   * rather than let the service miss a value; on another media's source, a reader of its own.
   */
  private static Reader<?> inputReader(String service, Source<?> source) {
    if (source instanceof MemorySource<?> memory) {
      return memory.serviceInput(service);
    }
    return source instanceof MediaSource<?> media ? media.serviceReader() : source.reader();
  }

  /** What a combinator does with one value of one input. */
  @FunctionalInterface
  interface InputStep {
    /**
     * @param input 0 for the first input
     * @param value its value
     */
    void accept(int input, Object value);
  }
}
