package dev.prime.test;

import static org.junit.platform.engine.discovery.DiscoverySelectors.selectClass;

import org.junit.platform.engine.TestExecutionResult;
import org.junit.platform.testkit.engine.EngineTestKit;

/**
 * Runs one test class through JUnit's engine in a JVM of its own and prints a line per test:
 * {@code RUN <display name>|<status>|<failure message>}.
 */
public final class KitMain {
  private KitMain() {}

  /**
   * @param args the test class's name
   * @throws ClassNotFoundException if there is no such class
   */
  public static void main(String[] args) throws ClassNotFoundException {
    EngineTestKit.engine("junit-jupiter")
        .selectors(selectClass(Class.forName(args[0])))
        .execute()
        .testEvents()
        .finished()
        .stream()
        .forEach(
            event -> {
              TestExecutionResult result = event.getPayload(TestExecutionResult.class).orElseThrow();
              System.out.println(
                  "RUN " + event.getTestDescriptor().getDisplayName() + "|" + result.getStatus()
                      + "|" + result.getThrowable().map(Throwable::getMessage).orElse(""));
            });
  }
}
