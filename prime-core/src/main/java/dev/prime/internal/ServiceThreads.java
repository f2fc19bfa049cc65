package dev.prime.internal;

import java.time.Duration;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Set;
import java.util.function.BooleanSupplier;
import java.util.function.Supplier;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * The service threads of one core: one named platform thread per asynchronous service.
 *
 * <p>Design: services declared before {@link #startAll()} wait; services added after it start at
 * once. Threads are daemons, so a core that was never closed cannot keep the JVM alive. Stopping
 * interrupts every thread and joins them against one shared deadline; a thread that ignores the
 * interrupt (a block stuck in uninterruptible I/O) is reported in one WARN line naming the core
 * and abandoned (a daemon, it ends when its block returns). A {@link VirtualMachineError} that
 * ends a service's thread is logged at ERROR under the service's name before it goes on to the
 * thread's uncaught-exception handler. A service may stop the services from its own thread (a
 * listener that closes its core): that thread is neither interrupted nor joined, since it cannot
 * wait for itself; its loop ends when it returns to read its closed source. A service whose thread
 * never ran (its core closed before it started) lets go of what it holds outside the thread (an
 * input on another core's source) through the release it was added with. All methods are
 * synchronized: they run on lifecycle calls, never per value.
 */
public final class ServiceThreads {
  private static final Logger LOG = LoggerFactory.getLogger(ServiceThreads.class);

  private final String coreName;
  private final String prefix;
  private final Map<String, Thread> threads = new LinkedHashMap<>();
  private final Map<String, Runnable> releases = new HashMap<>(); // run if the thread never ran
  private final Supplier<? extends RuntimeException> stoppedError;
  private boolean started;
  private volatile boolean stopped; // set before the services are interrupted; read by their marks

  /**
   * Whether the core whose own thread the current thread is has closed ({@link #markOwnThread});
   * {@code null} on a thread of no core (a user's).
   */
  private static final ThreadLocal<BooleanSupplier> OWNER_CLOSED = new ThreadLocal<>();

  /** This core's services' mark ({@link #markOwnThread}): whether they are stopped. */
  private final BooleanSupplier isStopped = () -> stopped;

  /**
   * @param coreName the core's name; threads are named {@code prime-<core>-<service>}
   * @param stoppedError what {@link #add} throws once the services are stopped (the core's
   *     closed exception)
   */
  public ServiceThreads(String coreName, Supplier<? extends RuntimeException> stoppedError) {
    this.coreName = coreName;
    this.prefix = threadPrefix(coreName);
    this.stoppedError = stoppedError;
  }

  /**
   * The prefix of the names of a core's service threads.
   *
   * @param coreName the core's name
   * @return {@code prime-<core>-}
   */
  public static String threadPrefix(String coreName) {
    return "prime-" + coreName + "-";
  }

  /**
   * Adds a service; it starts now if the services are started.
   *
   * @param service unique service name
   * @param body the service loop; must return when interrupted
   * @throws RuntimeException the constructor's {@code stoppedError} if the services are stopped:
   *     the core closed while the service was being declared
   */
  public synchronized void add(String service, Runnable body) {
    add(service, service, body);
  }

  /**
   * Adds a service whose thread is named after {@code service} but which logs as {@code shownAs}:
   * an in-memory link of a source runs, on a thread of its own, the service {@link
   * dev.prime.PrimeCore#serviceNames()} lists under its chain's name.
   *
   * @param service unique service name, for the thread
   * @param shownAs the name its ERROR line gives when a {@link VirtualMachineError} ends it
   * @param body the service loop; must return when interrupted
   * @throws RuntimeException the constructor's {@code stoppedError} if the services are stopped
   */
  public synchronized void add(String service, String shownAs, Runnable body) {
    add(service, shownAs, body, null);
  }

  /**
   * Adds a service that holds something outside its thread until its body ends, such as an input
   * opened on another core's source, which holds that source's publishers up: {@code release}
   * lets it go if the services stop before the thread ever ran (a core closed without being
   * started), when the body, which would have let it go, never runs.
   *
   * @param service unique service name, for the thread
   * @param shownAs the name its ERROR line gives when a {@link VirtualMachineError} ends it
   * @param body the service loop; must return when interrupted, and let go of what it holds
   * @param release lets go of what the body holds, if the body never runs; {@code null} for
   *     nothing; must not throw
   * @throws RuntimeException the constructor's {@code stoppedError} if the services are stopped
   *     (then {@code release} ran)
   */
  public synchronized void add(String service, String shownAs, Runnable body, Runnable release) {
    if (stopped) {
      if (release != null) {
        release.run(); // the core closed while the service was declared: it never runs
      }
      throw stoppedError.get();
    }
    if (threads.containsKey(service)) {
      throw new IllegalArgumentException("service '" + service + "' already exists");
    }
    Runnable logged = logFatal(shownAs, body);
    Thread thread =
        new Thread(
            () -> {
              markOwnThread(isStopped);
              logged.run();
            },
            prefix + service);
    thread.setDaemon(true);
    threads.put(service, thread);
    if (release != null) {
      releases.put(service, release);
    }
    if (started) {
      thread.start();
    }
  }

  /**
   * {@code body}, which logs a {@link VirtualMachineError} that ends it at ERROR under the
   * service's name and throws it on: such an error ends the service, never silently.
   */
  private static Runnable logFatal(String service, Runnable body) {
    return () -> {
      try {
        body.run();
      } catch (VirtualMachineError e) {
        LOG.error("service '{}' stops: {}", service, e.toString());
        throw e;
      }
    };
  }

  /** Starts every service added so far. */
  public synchronized void startAll() {
    if (stopped) {
      return; // close() overtook start(): the services must stay down
    }
    started = true;
    for (Thread thread : threads.values()) {
      if (thread.getState() == Thread.State.NEW) {
        thread.start();
      }
    }
  }

  /**
   * Whether {@code thread} is the thread of one of these services.
   *
   * @param thread a thread
   * @return whether a service runs on it
   */
  public synchronized boolean isServiceThread(Thread thread) {
    return threads.containsValue(thread);
  }

  /** The names of the services. */
  public synchronized Set<String> names() {
    return Set.copyOf(threads.keySet());
  }

  /**
   * Interrupts every service and waits for them until {@code timeout} has passed.
   *
   * @param timeout the whole wait
   * @return the names of services still running after it
   */
  public List<String> stopAll(Duration timeout) {
    List<Thread> toJoin;
    List<Runnable> neverRan = new ArrayList<>();
    synchronized (this) {
      stopped = true; // no thread starts from now on: one still new never runs
      toJoin = new ArrayList<>(threads.values());
      threads.forEach(
          (service, thread) -> {
            Runnable release = releases.get(service);
            if (release != null && thread.getState() == Thread.State.NEW) {
              neverRan.add(release);
            }
          });
      releases.clear();
    }
    neverRan.forEach(Runnable::run);
    toJoin.remove(Thread.currentThread()); // a service closing its own core
    for (Thread thread : toJoin) {
      thread.interrupt();
    }
    long deadline = System.nanoTime() + Deadlines.boundedNanos(timeout);
    List<String> stuck = new ArrayList<>();
    boolean interrupted = false;
    for (Thread thread : toJoin) {
      long left = deadline - System.nanoTime();
      try {
        if (left > 0 && thread.getState() != Thread.State.NEW) {
          thread.join(Math.max(1, left / 1_000_000));
        }
      } catch (InterruptedException e) {
        interrupted = true;
      }
      if (thread.isAlive()) {
        stuck.add(thread.getName());
      }
    }
    if (interrupted) {
      Thread.currentThread().interrupt();
    }
    if (!stuck.isEmpty()) {
      LOG.warn(
          "core '{}': services still running after {}, abandoned (daemon threads, each ends when"
              + " its block returns): {}",
          coreName,
          timeout,
          stuck);
    }
    return stuck;
  }

  /**
   * Clears the interrupt flag the user's code of a service set on the calling thread (a block that
   * restored the flag of an {@code InterruptedException} it caught), unless its core is closing:
   * the flag is cleared first and {@code closed} asked after, and a close marks its core closed
   * before it interrupts, so the flag of a close stays. Every media's services call it after
   * the user's code, before they go on.
   *
   * @param closed whether the service's core is closed; asked only when the flag was set
   */
  public static void clearOwnInterrupt(BooleanSupplier closed) {
    if (Thread.interrupted() && closed.getAsBoolean()) {
      Thread.currentThread().interrupt();
    }
  }

  /**
   * Marks the current thread as an own thread of a core (of any media: a service's, a listener's),
   * whose services clear the interrupt flag the user's code leaves while the core is open ({@link
   * #clearOwnInterrupt}); every service thread of this class is marked, and a media marks the
   * threads of its own. A call that waits for a reply ({@link #clearFlagLeftOnOwnThread}) is then
   * made without such a flag.
   *
   * @param closed whether the thread's core is closed (or its services stopped); its close must
   *     make it true before it interrupts the thread
   */
  public static void markOwnThread(BooleanSupplier closed) {
    OWNER_CLOSED.set(closed);
  }

  /**
   * Clears the interrupt flag of the current thread if it is a core's own thread ({@link
   * #markOwnThread}) whose core is open, and says whether it did: such a flag was left by the
   * user's code (a block that restored the flag of an {@code InterruptedException} it caught),
   * which the thread's service clears after the block, and is nobody's request to a call the
   * block makes of a chain that waits for a reply (another media's); the caller makes the call
   * without it and sets the flag again after it. The flag is cleared first and the core asked
   * after, as in {@link #clearOwnInterrupt}: a flag its close set is kept, and the call fails as an
   * interrupted one. A thread of no core (a user's) keeps its flag.
   *
   * @return whether the flag was set and cleared (the caller sets it again after its call)
   */
  public static boolean clearFlagLeftOnOwnThread() {
    Thread current = Thread.currentThread();
    if (!current.isInterrupted()) {
      return false;
    }
    BooleanSupplier closed = OWNER_CLOSED.get();
    if (closed == null || closed.getAsBoolean() || !Thread.interrupted()) {
      return false;
    }
    if (closed.getAsBoolean()) { // its close began meanwhile: the flag may be the close's
      current.interrupt();
      return false;
    }
    return true;
  }
}
