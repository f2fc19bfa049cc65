package dev.prime.conformance;

import dev.prime.Block;
import dev.prime.PrimeCore;
import java.util.ArrayList;
import java.util.List;

/**
 * The classes on the stack of a running chain's block: how the kit checks that an opt-in tap
 * (recording, metrics) is compiled into a chain when on and absent when off.
 */
final class RunningStack {
  private RunningStack() {}

  /**
   * Declares a chain named {@code frames} in {@code core}, starts the core and returns the class
   * names on the stack while the chain's block runs once.
   */
  static List<String> classesOfAChainIn(PrimeCore core) {
    Block<Integer, List<String>> frames =
        core.chain(
                "frames",
                (Integer x) -> {
                  List<String> classes = new ArrayList<>();
                  for (StackTraceElement frame : Thread.currentThread().getStackTrace()) {
                    classes.add(frame.getClassName());
                  }
                  return classes;
                })
            .toBlock();
    core.start();
    return frames.process(1);
  }
}
