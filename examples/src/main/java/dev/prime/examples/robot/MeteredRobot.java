package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.ServiceMetrics;
import dev.prime.metrics.PrimeMetrics;
import io.micrometer.core.instrument.MeterRegistry;
import io.micrometer.core.instrument.Timer;
import io.micrometer.core.instrument.simple.SimpleMeterRegistry;
import java.io.OutputStream;
import java.io.PrintStream;
import java.util.Locale;
import java.util.concurrent.TimeUnit;

/**
 * The robot with metrics: {@code metered-robot [liberty|radiant|optimus]} drives to the default
 * goal with the core's metrics on, bound to a Micrometer registry ({@link PrimeMetrics}), and
 * prints, for every metered service, what the registry's meters say: values in and out, failures,
 * the timer's count and mean, and the 50th and 99th percentiles of the core's histogram.
 *
 * <pre>{@code
 * ./mvnw -q -pl examples -am test-compile exec:java \
 *     -Dexec.mainClass=dev.prime.examples.robot.MeteredRobot -Dexec.args=optimus
 * }</pre>
 */
public final class MeteredRobot {
  private MeteredRobot() {}

  /**
   * Runs the example.
   *
   * @param args one media name, or none for Liberty
   */
  public static void main(String[] args) {
    if (args.length > 1) {
      System.err.println("usage: metered-robot [" + Media.knownNames().replace(", ", "|") + "]");
      System.exit(2);
    }
    Media media;
    try {
      media = args.length == 0 ? Media.LIBERTY : Media.byName(args[0]);
    } catch (IllegalArgumentException e) {
      System.err.println("error: " + e.getMessage());
      System.exit(2);
      return;
    }
    MeterRegistry registry = new SimpleMeterRegistry();
    SimulationResult result = run(media, registry, System.out);
    System.exit(result.reached() ? 0 : 1);
  }

  /**
   * Drives the robot on {@code media} with metrics bound to {@code registry} and prints the table.
   *
   * @param media the media
   * @param registry receives the core's meters (they stay registered: the core is closed, their
   *     last values remain readable)
   * @param out receives the table
   * @return the simulation's outcome
   */
  public static SimulationResult run(Media media, MeterRegistry registry, PrintStream out) {
    Mission mission = new Mission(new Goal(2.0, 1.0), 5_000, Integer.MAX_VALUE);
    CoreConfig config = CoreConfig.builder().name("robot").metrics(true).build();
    PrimeMetrics binder;
    SimulationResult result;
    try (PrimeCore core = media.create(config)) {
      // bound when the core starts: the diagram is declared by then, and no value has flowed
      binder = PrimeMetrics.of(core);
      core.whenRunning("metrics", () -> binder.bindTo(registry), () -> {});
      result =
          new RobotSimulation(RobotSpec.SMALL_INDOOR)
              .run(core, mission, new PrintStream(OutputStream.nullOutputStream()));
      out.printf(
          Locale.ROOT,
          "robot on media %s %s the goal after %d steps; its services' meters:%n",
          media.cliName(),
          result.reached() ? "reached" : "did NOT reach",
          result.steps());
      out.printf(
          Locale.ROOT,
          "  %-28s %-13s %7s %7s %8s %7s %9s %9s %9s%n",
          "service", "kind", "in", "out", "failures", "timed", "mean us", "p50 us", "p99 us");
      for (ServiceMetrics service : core.metrics().services()) {
        String name = service.name();
        Timer timer = registry.get(PrimeMetrics.PROCESSING).tag("service", name).timer();
        out.printf(
            Locale.ROOT,
            "  %-28s %-13s %7.0f %7.0f %8.0f %7d %9.1f %9.1f %9.1f%n",
            service.label(),
            service.kind(),
            count(registry, PrimeMetrics.VALUES_IN, name),
            count(registry, PrimeMetrics.VALUES_OUT, name),
            count(registry, PrimeMetrics.FAILURES, name),
            timer.count(),
            timer.mean(TimeUnit.MICROSECONDS),
            service.processing().percentileNanos(0.5) / 1000.0,
            service.processing().percentileNanos(0.99) / 1000.0);
      }
    }
    return result;
  }

  private static double count(MeterRegistry registry, String meter, String service) {
    return registry.get(meter).tag("service", service).functionCounter().count();
  }
}
