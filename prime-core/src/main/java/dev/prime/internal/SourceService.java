package dev.prime.internal;

import dev.prime.CoreClosedException;
import dev.prime.ErrorHandler;
import dev.prime.Reader;
import java.util.Objects;
import java.util.function.Consumer;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * The loop of an in-process asynchronous service: take a value from a reader, hand it to a step
 * (a chain's block and a publish, a filter, a listener), repeat until interrupted or closed.
 *
 * <p>A step that throws is reported to the error handler and the loop goes on with the next
 * value: a service never dies silently. Only an interrupt or a closed core ends it.
 *
 * @param <T> value type
 */
public final class SourceService<T> implements Runnable {
  private static final Logger LOG = LoggerFactory.getLogger(SourceService.class);

  private final String name;
  private final Reader<T> reader;
  private final Consumer<? super T> step;
  private final ErrorHandler errors;

  /**
   * @param name the service's name, for the error handler
   * @param reader where values come from
   * @param step what to do with each value
   * @param errors where failures go
   */
  public SourceService(String name, Reader<T> reader, Consumer<? super T> step, ErrorHandler errors) {
    this.name = Objects.requireNonNull(name, "name");
    this.reader = Objects.requireNonNull(reader, "reader");
    this.step = Objects.requireNonNull(step, "step");
    this.errors = Objects.requireNonNull(errors, "errors");
  }

  @Override
  public void run() {
    while (!Thread.currentThread().isInterrupted()) {
      T value;
      try {
        value = reader.take();
      } catch (InterruptedException | CoreClosedException e) {
        return;
      }
      try {
        step.accept(value);
      } catch (CoreClosedException e) {
        return;
      } catch (VirtualMachineError e) {
        throw e;
      } catch (Throwable e) {
        report(value, e);
      }
    }
  }

  private void report(T value, Throwable error) {
    try {
      errors.handle(name, value, error);
    } catch (RuntimeException handlerFailure) {
      handlerFailure.addSuppressed(error);
      LOG.error("the error handler failed for service '{}'", name, handlerFailure);
    }
  }
}
