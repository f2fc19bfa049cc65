package dev.prime.inspector;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.EventBlock;
import dev.prime.GenericService;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.Token;
import java.time.Duration;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;

/**
 * A controller shaped like the robot example's, with a few more kinds of node (a filter, a
 * listener, a reader, a timer, a generic service) so that the page draws every shape, and a
 * driver thread that runs control steps until stopped.
 */
final class DemoController implements AutoCloseable {
  /** Declares a demo controller on {@code core} (to watch, not to drive) and returns the core. */
  static PrimeCore declaredOn(PrimeCore core) {
    new DemoController(core);
    return core;
  }

  record Reading(long step, double left, double right) {}

  record Estimate(double x, double y, boolean moving) {}

  record Command(double leftVolts, double rightVolts) {}

  private final EventBlock<Reading> encoders = new EventBlock<>();
  private final Block<Token, Command> control;
  private final Reader<Estimate> watcher;
  private volatile boolean driving;
  private Thread driver;

  /** The name of the demo's failing listener. */
  static final String LISTENER = "listen(filter(encoders>odometry))";

  DemoController(PrimeCore core) {
    Source<Reading> readings = core.source("encoders", encoders);
    Source<Estimate> estimates =
        readings.then(
            core.chain("odometry", (Reading r) -> new Estimate(r.left() * 0.01, r.right() * 0.02, r.step() % 2 == 0)));
    Chain<Estimate, Command> drive =
        core.chain("planner", (Estimate e) -> new Estimate(1 - e.x(), 1 - e.y(), true))
            .then(core.chain("pid", (Estimate e) -> new Command(e.x() * 3, e.y() * 3)));
    Chain<Estimate, Command> guarded = core.guard(e -> e.x() < 1e9, drive, e -> new Command(0, 0));
    control = core.syncCollector(estimates).then(guarded).toBlock();
    // a listener that fails on every 20th value it gets, for the error figures
    AtomicLong heard = new AtomicLong();
    estimates.filter(Estimate::moving).listen(e -> {
      if (heard.incrementAndGet() % 20 == 0) {
        throw new IllegalStateException("the demo's listener fails on every 20th value");
      }
    });
    watcher = estimates.reader();
    core.timer("heartbeat", Duration.ofMillis(200));
    core.service("watchdog", new GenericService() {
      @Override
      public void work() throws InterruptedException {
        TimeUnit.MILLISECONDS.sleep(100);
      }
    });
  }

  /** Runs control steps on a thread of its own, about one every {@code pauseMillis}, until {@link #stop()}. */
  void drive(long pauseMillis) {
    driving = true;
    driver =
        new Thread(
            () -> {
              for (long step = 0; driving; step++) {
                encoders.publish(new Reading(step, step, 2.0 * step));
                control.process(Token.INSTANCE);
                watcher.drain();
                try {
                  Thread.sleep(pauseMillis); // pacing the demo, not synchronising anything
                } catch (InterruptedException e) {
                  return;
                }
              }
            },
            "demo-driver");
    driver.start();
  }

  /** Stops driving and waits (bounded) for the driver to end. */
  void stop() {
    driving = false;
    if (driver != null) {
      try {
        driver.join(10_000);
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
        throw new AssertionError("interrupted while stopping the demo's driver", e);
      }
      if (driver.isAlive()) {
        driver.interrupt();
        throw new AssertionError("the demo's driver did not stop within 10 s");
      }
    }
  }

  @Override
  public void close() {
    stop();
    watcher.close();
  }
}
