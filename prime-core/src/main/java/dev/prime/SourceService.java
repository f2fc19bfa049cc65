package dev.prime;

import java.util.Objects;
import java.util.function.BooleanSupplier;
import java.util.function.Consumer;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * The loop of an in-process asynchronous service: take a value from a reader, hand it to a step
 * (a chain's block and a publish, a filter, a listener), repeat until interrupted or closed.
 *
 * <p>A step that throws anything but a {@link VirtualMachineError} is reported to the error
 * handler and the loop goes on with the next value: a service never dies silently. The handler
 * gets what the user wrote: a {@link ChainFailedException} (a chain's block failed) is reported
 * under the name of the chain that failed, with the block's own throwable, not the wrapper. Only
 * the closing of the core that runs it (which interrupts it), an interrupt while it waits for a
 * value, or the closing of its input source ends it. A step that interrupts its own thread while
 * the core is open (a block that restores the flag of an {@code InterruptedException} it caught)
 * does not: the loop clears that flag after the step and goes on. Nor does a value the core's
 * copy codec cannot decode ({@link UndecodableValueException}, thrown by the read): it goes to
 * the error handler under the service's name, with the encoded bytes as the input, and the loop
 * goes on with the next value.
 *
 * <p>An input that is a {@link BatchReader} (an in-memory service input) is drained in batches:
 * one call hands the loop every value available, each handled as above, instead of one {@link
 * Reader#take()} per value. The loop checks for an interrupt after every value either way.
 *
 * @param <T> value type
 */
final class SourceService<T> implements Runnable {
  private static final Logger LOG = LoggerFactory.getLogger(SourceService.class);

  private final String name;
  private final Reader<T> reader;
  private final Consumer<? super T> step;
  private final ErrorHandler errors;
  private final BooleanSupplier ownerClosed;
  private final BatchReader.Sink<T> handler = this::handle; // made once: batches allocate nothing
  private boolean ended; // the owner closed under a step: the loop ends

  /**
   * @param name the service's name, for the error handler
   * @param reader where values come from
   * @param step what to do with each value
   * @param errors where failures go
   * @param ownerClosed whether the core running this service is closed: a CoreClosedException
   *     from the step ends the service only then (a closed foreign core is an ordinary failure)
   */
  SourceService(
      String name,
      Reader<T> reader,
      Consumer<? super T> step,
      ErrorHandler errors,
      BooleanSupplier ownerClosed) {
    this.name = Objects.requireNonNull(name, "name");
    this.reader = Objects.requireNonNull(reader, "reader");
    this.step = Objects.requireNonNull(step, "step");
    this.errors = Objects.requireNonNull(errors, "errors");
    this.ownerClosed = Objects.requireNonNull(ownerClosed, "ownerClosed");
  }

  /** Runs the loop; closes the reader when the loop ends, so it no longer holds publishers up. */
  @Override
  public void run() {
    try {
      loop();
    } finally {
      reader.close();
    }
  }

  private void loop() {
    BatchReader<T> batches = batches(reader);
    while (!ended && !Thread.currentThread().isInterrupted()) {
      try {
        if (batches != null) {
          batches.takeAvailable(handler);
        } else {
          handle(reader.take());
        }
      } catch (InterruptedException e) {
        return;
      } catch (UndecodableValueException e) {
        // the codec could not decode a copy of the value: reported as a failure, the value skipped
        FailureReport.report(errors, name, e.encoded(), e);
      } catch (CoreClosedException e) {
        if (!ownerClosed.getAsBoolean()) {
          LOG.warn("service '{}' stops: its input source belongs to a closed core", name, e);
        }
        return;
      }
    }
  }

  @SuppressWarnings("unchecked")
  private static <T> BatchReader<T> batches(Reader<T> reader) {
    return reader instanceof BatchReader<?> batches ? (BatchReader<T>) batches : null;
  }

  /**
   * Runs the step on one value; a failure is reported, not thrown.
   *
   * @return whether to go on: false once interrupted by the owner's close or once the owner
   *     closed under the step
   */
  private boolean handle(T value) {
    try {
      step.accept(value);
    } catch (CoreClosedException e) {
      if (ownerClosed.getAsBoolean()) {
        ended = true;
        return false;
      }
      report(value, e); // another core closed under this step: an ordinary failure, go on
    } catch (VirtualMachineError e) {
      throw e;
    } catch (Throwable e) {
      report(value, e);
    }
    return !interruptedByClose();
  }

  /**
   * Whether this thread's interrupt flag ends the loop: only once the owner is closed, which
   * happens before it interrupts its services. A flag the step set on its own thread while the
   * owner is open is cleared (cleared first, then the owner looked at: an interrupt by a close
   * that comes meanwhile is kept).
   */
  private boolean interruptedByClose() {
    if (!Thread.interrupted()) {
      return false;
    }
    if (ownerClosed.getAsBoolean()) {
      Thread.currentThread().interrupt();
      return true;
    }
    return false;
  }

  private void report(T value, Throwable error) {
    FailureReport.report(errors, name, value, error);
  }

}
