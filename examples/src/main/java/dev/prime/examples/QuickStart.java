package dev.prime.examples;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.liberty.LibertyCore;
import java.io.PrintStream;

/**
 * The README's quick start, compiled and tested so that the README never shows code that does
 * not build: write a block, make chains, link them, run them.
 */
public final class QuickStart {

  private QuickStart() {}

  /**
   * Prints what the quick start computes.
   *
   * @param args ignored
   * @throws InterruptedException if interrupted while waiting for the source
   */
  public static void main(String[] args) throws InterruptedException {
    run(System.out);
  }

  /**
   * The quick start itself.
   *
   * @param out where the results go
   * @throws InterruptedException if interrupted while waiting for the source
   */
  public static void run(PrintStream out) throws InterruptedException {
    // quick-start:begin
    // 1. A block is a plain function: no framework types inside, unit-test it with plain JUnit.
    Block<Double, Double> celsiusToFahrenheit = c -> c * 9 / 5 + 32;

    // 2. A core turns blocks into chains. This line picks the media; nothing else changes.
    try (PrimeCore core = new LibertyCore()) {
      // 3. Link chains with then(): the result is one chain.
      Chain<Double, String> report =
          core.chain("convert", celsiusToFahrenheit)
              .then(core.chain("format", (Double f) -> Math.round(f) + " F"));

      // 4. An event block publishes values (a sensor); the core makes it a source, and linking
      //    a chain to the source runs the chain as a service on every value.
      EventBlock<Double> thermometer = new EventBlock<>();
      Source<String> reports = core.source("thermometer", thermometer).then(report);
      Reader<String> display = reports.reader();

      // 5. Or call a chain directly: toBlock() turns it back into a plain function.
      Block<Double, Double> convert = core.chain(celsiusToFahrenheit).toBlock();

      core.start();
      thermometer.publish(21.5);
      out.println(display.take()); // 71 F
      out.println(convert.process(100.0)); // 212.0
    }
    // quick-start:end
  }
}
