package dev.prime;

import dev.prime.internal.Deadlines;
import java.util.ArrayList;
import java.util.List;
import java.util.Objects;
import java.util.Set;
import java.util.concurrent.TimeUnit;
import org.slf4j.LoggerFactory;

/**
 * The hooks of {@link PrimeCore#whenRunning}: work tied to a core's lifecycle that is not a
 * service of its diagram (a Kotlin flow feeding a source, a metrics binder).
 *
 * <p>Design note. The list, the two flags and each hook's state are guarded by this object;
 * hooks run outside the lock, so a hook may call the core. A hook added after the core started
 * runs its start at once on the adding thread; a hook added after the core closed is refused. A
 * hook's {@code onClose} runs once, and always after its {@code onStart} if that ran: a hook is
 * claimed for its start under the lock (it is then {@link Phase#STARTING}), and {@link #closing}
 * does not start the hooks not yet claimed, closes them at once, and waits for those starting
 * (on another thread, at most the core's shutdown timeout) before closing them. A start the close
 * cannot wait for (it runs on the closing thread, which closed from within {@code onStart}, or on
 * one of the core's own threads, or it outlasts the wait or an interrupt ends it) is closed by its
 * starting thread as soon as its {@code onStart} returns. A hook that throws goes to the core's
 * error handler; a handler that throws in turn is logged and ignored, as for a service.
 */
final class LifecycleHooks {
  /** Where a hook is in its life. */
  private enum Phase {
    /** Not started. */
    NEW,
    /** Its {@code onStart} runs, on {@link Hook#starter}. */
    STARTING,
    /** Its {@code onStart} returned (or threw). */
    STARTED,
    /** Its {@code onClose} was given to a thread to run; nothing more happens to it. */
    CLOSED
  }

  /** One hook; its mutable fields are guarded by the {@link LifecycleHooks} that holds it. */
  private static final class Hook {
    final String name;
    final Runnable onStart;
    final Runnable onClose;
    Phase phase = Phase.NEW;
    Thread starter;
    /** Set by a close that could not wait for the start: the starter closes it when done. */
    boolean closeWhenStarted;

    Hook(String name, Runnable onStart, Runnable onClose) {
      this.name = name;
      this.onStart = onStart;
      this.onClose = onClose;
    }
  }

  private final PrimeCore core;
  private final List<Hook> hooks = new ArrayList<>(); // guarded by this
  private boolean started; // guarded by this
  private boolean closed; // guarded by this

  LifecycleHooks(PrimeCore core) {
    this.core = core;
  }

  void add(String name, Runnable onStart, Runnable onClose) {
    Hook hook =
        new Hook(
            Objects.requireNonNull(name, "name must not be null"),
            Objects.requireNonNull(onStart, "onStart must not be null"),
            Objects.requireNonNull(onClose, "onClose must not be null"));
    synchronized (this) {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      hooks.add(hook);
      if (!started) {
        return;
      }
      claim(hook);
    }
    start(hook);
  }

  void started() {
    List<Hook> starting;
    synchronized (this) {
      if (closed) {
        return;
      }
      started = true;
      starting = List.copyOf(hooks);
    }
    for (Hook hook : starting) {
      synchronized (this) {
        if (closed || hook.phase != Phase.NEW) {
          continue; // a close came meanwhile: it closed the hooks not started
        }
        claim(hook);
      }
      start(hook);
    }
  }

  /** Marks {@code hook} as started by this thread; under the lock. */
  private void claim(Hook hook) {
    hook.phase = Phase.STARTING;
    hook.starter = Thread.currentThread();
  }

  /** Runs a claimed hook's start, then its close if a close came meanwhile and left it that. */
  private void start(Hook hook) {
    boolean closeNow;
    try {
      run(hook.name, "start", hook.onStart);
    } finally {
      synchronized (this) {
        hook.starter = null;
        closeNow = hook.closeWhenStarted;
        hook.phase = closeNow ? Phase.CLOSED : Phase.STARTED;
        notifyAll();
      }
    }
    if (closeNow) {
      run(hook.name, "close", hook.onClose);
    }
  }

  void closing() {
    List<Hook> closing;
    synchronized (this) {
      closed = true;
      closing = List.copyOf(hooks);
      hooks.clear();
    }
    long deadline = System.nanoTime() + Deadlines.boundedNanos(core.config().shutdownTimeout());
    for (Hook hook : closing) {
      if (awaitStarted(hook, deadline)) {
        run(hook.name, "close", hook.onClose);
      }
    }
  }

  /**
   * Waits, if it may, until {@code hook} is not starting, and claims it for its close.
   *
   * @return whether this thread closes it now; if not, its starter closes it once started
   */
  private synchronized boolean awaitStarted(Hook hook, long deadline) {
    Thread current = Thread.currentThread();
    boolean interrupted = false;
    try {
      while (hook.phase == Phase.STARTING
          && hook.starter != current
          && !core.isOwnThread(current)
          && !interrupted) {
        long left = deadline - System.nanoTime();
        if (left <= 0) {
          LoggerFactory.getLogger(PrimeCore.class)
              .warn(
                  "core '{}': the start of hook '{}' has not returned within the shutdown timeout;"
                      + " it will be closed when its start returns",
                  core.name(),
                  hook.name);
          break;
        }
        try {
          TimeUnit.NANOSECONDS.timedWait(this, left);
        } catch (InterruptedException e) {
          interrupted = true;
        }
      }
    } finally {
      if (interrupted) {
        current.interrupt();
      }
    }
    if (hook.phase == Phase.STARTING) {
      hook.closeWhenStarted = true;
      return false;
    }
    hook.phase = Phase.CLOSED;
    return true;
  }

  private void run(String name, String phase, Runnable action) {
    try {
      action.run();
    } catch (VirtualMachineError fatal) {
      throw fatal;
    } catch (Throwable e) { // a checked exception thrown sneakily (a Kotlin hook's) too
      // a handler that throws is logged, so start() and close() carry on whole
      FailureReport.handle(core.config().errorHandler(), name, phase, e);
    }
  }

  /** The most service names the start line lists (a core may have thousands). */
  private static final int START_LINE_SERVICES = 20;

  /** Logs the one INFO line of {@link PrimeCore#start()}: the core, its media, what it hosts. */
  static void logStarted(PrimeCore core, String media, String details, Set<String> services) {
    List<String> hosted = List.copyOf(services);
    LoggerFactory.getLogger(PrimeCore.class)
        .info(
            "core '{}' started on {}{}, hosting services {}{}",
            core.name(),
            media,
            details,
            hosted.subList(0, Math.min(hosted.size(), START_LINE_SERVICES)),
            hosted.size() > START_LINE_SERVICES
                ? " and " + (hosted.size() - START_LINE_SERVICES) + " more"
                : "");
  }
}
