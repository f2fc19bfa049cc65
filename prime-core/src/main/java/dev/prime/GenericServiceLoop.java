package dev.prime;

import dev.prime.GenericService.Step;
import dev.prime.internal.Deadlines;
import java.time.Duration;
import java.util.Objects;
import java.util.concurrent.TimeUnit;
import java.util.function.BooleanSupplier;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * Runs one {@link GenericService} on the thread that calls {@link #run()}: initialize (again after
 * a back-off until it succeeds), work until stopped, shut down. Every media runs a generic service
 * through this class, so the contract documented on {@link GenericService} is the same on each; a
 * media only chooses the thread and when to start it.
 *
 * <p>Design note. The service is stopped by two signals together: the media's {@code stopping}
 * condition (the core closed; on Optimus also the service lost to another host) and an interrupt
 * of the running thread, which ends a {@code work} or a back-off that waits. The condition is
 * what the loop trusts: an interrupt alone (a stray one from user code) is a failure of the step
 * it ended, reported and followed by the next step, and whatever a step throws once the
 * condition holds is the end of that step, not a failure. {@code shutdown} runs with the interrupt
 * flag cleared, and the flag is set again afterwards so the thread's owner still sees it. Runs
 * once: a second {@link #run()} is refused.
 */
public final class GenericServiceLoop implements Runnable {
  private static final Logger LOG = LoggerFactory.getLogger(GenericServiceLoop.class);

  private final String name;
  private final GenericService service;
  private final ErrorHandler errors;
  private final BooleanSupplier stopping;
  private boolean ran; // guarded by this

  /**
   * @param name the service's name, as the error handler reports it
   * @param service the user's service
   * @param errors where failures go
   * @param stopping whether the service must stop; a media sets it before it interrupts the
   *     thread running {@link #run()}
   */
  public GenericServiceLoop(
      String name, GenericService service, ErrorHandler errors, BooleanSupplier stopping) {
    this.name = Objects.requireNonNull(name, "name");
    this.service = Objects.requireNonNull(service, "service");
    this.errors = Objects.requireNonNull(errors, "errors");
    this.stopping = Objects.requireNonNull(stopping, "stopping");
  }

  /** {@return the service's name} */
  public String name() {
    return name;
  }

  /**
   * Runs the service until {@code stopping} holds; returns after its {@code shutdown}.
   *
   * @throws IllegalStateException if it ran before
   */
  @Override
  public void run() {
    synchronized (this) {
      if (ran) {
        throw new IllegalStateException("generic service '" + name + "' already ran");
      }
      ran = true;
    }
    if (!initialize()) {
      return;
    }
    try {
      workUntilStopped();
    } finally {
      shutdown();
    }
  }

  /** Calls initialize until it succeeds (true) or the service stops first (false). */
  private boolean initialize() {
    int failures = 0;
    while (!stopping.getAsBoolean()) {
      try {
        service.initialize();
        return true;
      } catch (VirtualMachineError e) {
        throw e;
      } catch (Throwable e) {
        if (stopping.getAsBoolean()) {
          return false;
        }
        report(Step.INITIALIZE, e);
        failures++;
      }
      backOff(failures);
    }
    return false;
  }

  private void workUntilStopped() {
    int failures = 0;
    while (!stopping.getAsBoolean()) {
      try {
        service.work();
        failures = 0;
        continue;
      } catch (VirtualMachineError e) {
        throw e;
      } catch (Throwable e) {
        if (stopping.getAsBoolean()) {
          return;
        }
        report(Step.WORK, e);
        failures++;
      }
      backOff(failures);
    }
  }

  private void shutdown() {
    boolean interrupted = Thread.interrupted();
    try {
      service.shutdown();
    } catch (VirtualMachineError e) {
      throw e;
    } catch (Throwable e) {
      report(Step.SHUTDOWN, e);
    } finally {
      if (interrupted) {
        Thread.currentThread().interrupt();
      }
    }
  }

  /** Waits the service's back-off; an interrupt ends the wait (the loop then checks stopping). */
  private void backOff(int failures) {
    Duration wait;
    try {
      wait = service.backoff(failures);
    } catch (VirtualMachineError e) {
      throw e;
    } catch (Throwable e) { // an Error or a checked exception too: only the JVM's trouble ends it
      LOG.warn("generic service '{}': its backoff({}) failed; waiting 1 s", name, failures, e);
      wait = Duration.ofSeconds(1);
    }
    if (wait == null || wait.isNegative() || wait.isZero()) {
      return;
    }
    try {
      TimeUnit.NANOSECONDS.sleep(Deadlines.boundedNanos(wait));
    } catch (InterruptedException e) {
      // stopping is checked next; a stray interrupt only shortens this wait
    }
  }

  /**
   * Reports a failed step as every service does: a {@link ChainFailedException} (the step called a
   * chain whose block failed) under the failing chain's name, with the block's own throwable.
   */
  private void report(Step step, Throwable error) {
    FailureReport.report(errors, name, step, error);
  }

}
