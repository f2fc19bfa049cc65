package dev.prime.test;

import static org.junit.platform.engine.discovery.DiscoverySelectors.selectClass;

import java.util.concurrent.Callable;
import org.junit.jupiter.engine.JupiterTestEngine;
import org.junit.platform.launcher.Launcher;
import org.junit.platform.launcher.core.LauncherDiscoveryRequestBuilder;
import org.junit.platform.launcher.core.LauncherFactory;
import org.junit.platform.launcher.listeners.SummaryGeneratingListener;
import org.junit.platform.launcher.listeners.TestExecutionSummary;

/**
 * Runs {@link ClassEndCleanupRun} through the JUnit launcher of the class loader this class is
 * loaded in (for {@link ClassEndCleanupTest}: one with an older JUnit, the thread's context class
 * loader set to it), with the API every JUnit 5 has.
 */
public final class OldestJUnitLauncher implements Callable<String> {

  /** For the reflective call. */
  public OldestJUnitLauncher() {}

  /** {@return the Jupiter engine's version, and how many tests succeeded and failed, with the failures} */
  @Override
  public String call() {
    Launcher launcher = LauncherFactory.create();
    SummaryGeneratingListener listener = new SummaryGeneratingListener();
    launcher.execute(
        LauncherDiscoveryRequestBuilder.request().selectors(selectClass(ClassEndCleanupRun.class)).build(),
        listener);
    TestExecutionSummary summary = listener.getSummary();
    StringBuilder failures = new StringBuilder();
    for (TestExecutionSummary.Failure failure : summary.getFailures()) {
      failures.append("; ").append(failure.getTestIdentifier().getDisplayName()).append(": ")
          .append(failure.getException());
    }
    return "Jupiter " + new JupiterTestEngine().getVersion().orElse("?") + ": "
        + summary.getTestsSucceededCount() + " succeeded, " + summary.getTestsFailedCount()
        + " failed" + failures;
  }
}
