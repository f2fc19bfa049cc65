package dev.prime.faults;

import dev.prime.CoreConfig;
import dev.prime.ErrorHandler;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.List;

/** The Optimus cores the tests themselves run (workers make theirs in {@link FaultWorkerMain}). */
final class Cores {
  private Cores() {}

  /** A core named {@code name} on {@code url} with {@code retention}, hosting only {@code hosts}. */
  static OptimusCore core(String url, String name, int retention, String... hosts) {
    return builder(url, name, retention, null).hosts(List.of(hosts)).build();
  }

  /** A builder with the suite's defaults: a 10 s call timeout and the given error handler (null: the default). */
  static OptimusCore.Builder builder(String url, String name, int retention, ErrorHandler handler) {
    CoreConfig.Builder config = CoreConfig.builder().name(name).sourceRetention(retention);
    if (handler != null) config.errorHandler(handler);
    return OptimusCore.builder().config(config.build()).redis(url).callTimeout(Duration.ofSeconds(10));
  }
}
