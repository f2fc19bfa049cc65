package dev.prime.examples;

// testing:begin
import static dev.prime.test.ReaderAssert.assertThat;

import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.test.PrimeTest;
import java.time.Duration;

class ThermometerTest {

  @PrimeTest // runs once on Liberty, once on Radiant, once on Optimus, each with a fresh core
  void reportsEveryReadingInFahrenheit(PrimeCore core) {
    EventBlock<Double> thermometer = new EventBlock<>();
    Reader<String> display =
        core.source("thermometer", thermometer)
            .then(core.chain("convert", (Double c) -> c * 9 / 5 + 32))
            .then(core.chain("format", (Double f) -> Math.round(f) + " F"))
            .reader();
    core.start();

    thermometer.publish(21.5);
    thermometer.publish(100.0);

    assertThat(display)
        .within(Duration.ofSeconds(5)) // each step waits at most 5 s; no sleeps
        .emits("71 F", "212 F")
        .emitsNothingWithin(Duration.ofMillis(100));
    core.close();
    assertThat(display).completes(); // a reader ends when its core closes
  }
}
// testing:end
