package dev.prime;

import java.util.ArrayList;
import java.util.List;
import java.util.Objects;
import java.util.Set;
import org.slf4j.LoggerFactory;

/**
 * The hooks of {@link PrimeCore#whenRunning}: work tied to a core's lifecycle that is not a
 * service of its diagram (a Kotlin flow feeding a source).
 *
 * <p>Design note. The list and the two flags are guarded by this object; hooks run outside the
 * lock, so a hook may call the core. A hook added after the core started runs its start at once
 * on the adding thread; a hook added after the core closed is refused. If {@code close()} races
 * with adding a hook to a started core, the hook's close may run before its start: the close is
 * still called exactly once, and a hook must tolerate that order (cancel first, launch later is a
 * no-op on a cancelled coroutine scope). A hook that throws goes to the core's error handler; a
 * handler that throws in turn is logged and ignored, as for a service.
 */
final class LifecycleHooks {
  private record Hook(String name, Runnable onStart, Runnable onClose) {}

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
    boolean startNow;
    synchronized (this) {
      if (closed) {
        throw new CoreClosedException(core.name());
      }
      hooks.add(hook);
      startNow = started;
    }
    if (startNow) {
      run(hook.name(), "start", hook.onStart());
    }
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
    starting.forEach(hook -> run(hook.name(), "start", hook.onStart()));
  }

  void closing() {
    List<Hook> closing;
    synchronized (this) {
      closed = true;
      closing = List.copyOf(hooks);
      hooks.clear();
    }
    closing.forEach(hook -> run(hook.name(), "close", hook.onClose()));
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
