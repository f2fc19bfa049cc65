package dev.prime;

import java.time.Duration;

/**
 * A long-running service of the logic layer that is not fed by a source: a hardware driver that
 * reads a serial port, a poller that asks a web service every second. Give it to {@link
 * PrimeCore#service(String, GenericService)}; the core runs it from {@link PrimeCore#start()} (at
 * once if the core is started) until {@link PrimeCore#close()}, on every media, like any service.
 *
 * <pre>{@code
 * core.service("lidar", new GenericService() {
 *   private SerialPort port;
 *   public void initialize() throws IOException { port = SerialPort.open("/dev/ttyUSB0"); }
 *   public void work() throws IOException { scans.publish(Scan.parse(port.readFrame())); }
 *   public void shutdown() { port.close(); }
 * });
 * }</pre>
 *
 * <h2>Contract</h2>
 * <ul>
 *   <li><b>Threading.</b> {@link #initialize()}, every {@link #work()} and {@link #shutdown()} run
 *       one after the other on one thread of the service's own, never concurrently: state kept in
 *       fields needs no locks. Publishing to an {@link EventBlock} from {@code work} is how a
 *       generic service feeds a source.
 *   <li><b>Steps.</b> {@code initialize} runs once before the first {@code work}. {@code work}
 *       runs again as soon as it returns: it should itself wait for its next piece of work (a
 *       blocking read, a sleep until the next poll); a {@code work} that returns at once keeps a
 *       core busy. {@code shutdown} runs once, after the last {@code work}, if and only if
 *       {@code initialize} returned normally.
 *   <li><b>Failures.</b> Anything {@code initialize}, {@code work} or {@code shutdown} throws
 *       (but a {@link VirtualMachineError}, which ends the service: it is not reported, and no
 *       step runs after it but {@code shutdown}, at once) goes to the core's {@link
 *       ErrorHandler} with the service's name, the {@link Step} that failed as the input and the
 *       throwable itself (as for every service, a {@link ChainFailedException} from a chain the
 *       step called is reported under that chain's name, with its block's own throwable). The
 *       service then goes on: a failed {@code initialize} is tried again,
 *       a failed {@code work} is followed by the next {@code work}, each after the {@link
 *       #backoff(int) back-off} (so a driver whose device is unplugged does not spin a core).
 *       The back-off starts again after a step that succeeds.
 *   <li><b>Stopping.</b> {@link PrimeCore#close()} (or, on a media that spreads services over
 *       processes, losing the service to another process) interrupts the service's thread: a
 *       {@code work} that waits must wait interruptibly ({@link Thread#sleep}, {@link
 *       java.util.concurrent.BlockingQueue#take}, interruptible channels) or with a timeout.
 *       Whatever {@code work} throws while the service is stopping is taken as the end of that
 *       step, not reported. Then {@code shutdown} runs, with the thread's interrupt flag cleared
 *       so it can release what it holds; {@code close()} waits for all of it up to {@link
 *       CoreConfig#shutdownTimeout()}. A {@code work} stuck in uninterruptible I/O cannot be
 *       stopped: close it from elsewhere, or use a timeout.
 *   <li><b>Hosting.</b> A generic service is a service of the topology (a {@link
 *       dev.prime.topology.TopologyNode.GenericServiceNode}); on a media that spreads services
 *       over processes (Optimus) it runs only in the process that hosts it, so several processes
 *       may declare it and exactly one runs it.
 * </ul>
 *
 * <p>Only {@link #work()} must be written, so a simple poller is a lambda: {@code
 * core.service("poller", () -> { readings.publish(sensor.read()); Thread.sleep(100); })}.
 */
@FunctionalInterface
public interface GenericService {

  /**
   * Prepares the service (opens a port, connects a device), once, before the first {@link
   * #work()}. The default does nothing.
   *
   * @throws Exception reported to the error handler; {@code initialize} is tried again after the
   *     back-off, and {@code work} does not run until it succeeds
   */
  default void initialize() throws Exception {}

  /**
   * One step of the service's work; called again as soon as it returns, until the service stops.
   * Waits for its work itself (see the class docs), interruptibly.
   *
   * @throws Exception reported to the error handler; the next {@code work} runs after the
   *     back-off
   */
  void work() throws Exception;

  /**
   * Releases what {@link #initialize()} acquired, once, when the service stops, if {@code
   * initialize} succeeded. The default does nothing.
   *
   * @throws Exception reported to the error handler
   */
  default void shutdown() throws Exception {}

  /**
   * How long to wait before the next step after {@code failures} failures in a row of {@code
   * initialize} or {@code work}. The default doubles from 10 ms up to 1 s: 10 ms, 20 ms, 40 ms,
   * ..., 640 ms, 1 s, 1 s, ... The wait ends at once when the service stops.
   *
   * @param failures how many steps failed in a row, 1 or more
   * @return the wait, zero or more
   */
  default Duration backoff(int failures) {
    return FailureBackoff.after(failures);
  }

  /** Which step of a generic service failed: the input its {@link ErrorHandler} receives. */
  enum Step {
    /** {@link GenericService#initialize()} failed; it is tried again. */
    INITIALIZE,
    /** {@link GenericService#work()} failed; the next one runs. */
    WORK,
    /** {@link GenericService#shutdown()} failed; the service has ended. */
    SHUTDOWN
  }
}
