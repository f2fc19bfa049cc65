package dev.prime.faults;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.EmbeddedRedis;
import dev.prime.optimus.OptimusCore;
import java.io.BufferedReader;
import java.io.IOException;
import java.io.InputStreamReader;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import redis.clients.jedis.HostAndPort;
import redis.clients.jedis.Jedis;

/**
 * The main class of the suite's worker JVMs ({@link WorkerJvm}). Modes:
 *
 * <ul>
 *   <li>{@code stream URL CORE RETENTION GENERATION}: declares {@link StreamTopology#declareStream}
 *       and hosts {@code stamp}, marking values with GENERATION;
 *   <li>{@code large URL CORE}: declares {@link StreamTopology#declareLarge} and hosts
 *       {@code measure} and {@code size} (run it with a small {@code -Xmx});
 *   <li>{@code readers URL CORE COUNT}: declares the stream topology, hosts nothing, and opens
 *       COUNT readers of source {@code ids} (which a kill leaves behind);
 *   <li>{@code embedded}: starts an {@link EmbeddedRedis} (the binary the project resolves) and
 *       pings it.
 * </ul>
 *
 * It prints {@code READY ...} once running (or {@code REFUSED <message>} and exits with 3 if
 * {@code start()} refuses), prints failures its error handler sees as {@code ERROR ...}, and stops
 * when its standard input ends or gives a line {@code STOP}. A shutdown hook closes the core, so
 * SIGTERM is a graceful stop.
 */
public final class FaultWorkerMain {
  private FaultWorkerMain() {}

  public static void main(String[] args) throws Exception {
    if (args.length == 0) usage();
    switch (args[0]) {
      case "stream":
        if (args.length != 5) usage();
        run(args[1], args[2], Integer.parseInt(args[3]), "stamp",
            core -> StreamTopology.declareStream(core, new EventBlock<>(), Integer.parseInt(args[4]), false));
        break;
      case "large":
        if (args.length != 3) usage();
        run(args[1], args[2], StreamTopology.WIDE_RETENTION, "measure,size",
            core -> StreamTopology.declareLarge(core, new EventBlock<>(), false));
        break;
      case "readers":
        if (args.length != 4) usage();
        int count = Integer.parseInt(args[3]);
        List<Reader<Long>> readers = new ArrayList<>();
        run(args[1], args[2], 1024, "", core -> {
          Source<Long> ids = core.source("ids", new EventBlock<Long>());
          for (int i = 0; i < count; i++) readers.add(ids.reader());
        });
        break;
      case "embedded":
        embedded();
        break;
      default:
        usage();
    }
  }

  private interface Declaration {
    void declare(OptimusCore core);
  }

  private static void run(String url, String coreName, int retention, String hosted, Declaration declaration) throws IOException {
    CoreConfig config = CoreConfig.builder()
        .name(coreName)
        .sourceRetention(retention)
        .errorHandler((service, input, error) -> System.out.println("ERROR in " + service + ": " + error))
        .build();
    List<String> hosts = hosted.isEmpty() ? List.of() : List.of(hosted.split(","));
    OptimusCore core = OptimusCore.builder().config(config).redis(url).hosts(hosts).build();
    Thread closer = new Thread(core::close, "fault-worker-close");
    Runtime.getRuntime().addShutdownHook(closer);
    declaration.declare(core);
    try {
      core.start();
    } catch (IllegalStateException e) {
      System.out.println("REFUSED " + e.getMessage());
      System.out.flush();
      System.exit(3); // the shutdown hook closes the core
    }
    System.out.println("READY hosting " + core.serviceNames().stream().sorted().toList() + " pid " + ProcessHandle.current().pid());
    System.out.flush();
    awaitStop();
    System.out.println("STOPPED");
    System.out.flush();
    System.exit(0); // the shutdown hook closes the core
  }

  private static void embedded() throws IOException {
    try (EmbeddedRedis redis = EmbeddedRedis.start();
        Jedis jedis = new Jedis(new HostAndPort("127.0.0.1", redis.getPort()))) {
      System.out.println("STARTED " + redis.getUri() + " " + jedis.ping());
    } catch (RuntimeException e) {
      System.out.println("FAILED " + e);
    }
    System.out.flush();
  }

  private static void awaitStop() throws IOException {
    BufferedReader in = new BufferedReader(new InputStreamReader(System.in, StandardCharsets.UTF_8));
    for (String line = in.readLine(); line != null; line = in.readLine()) {
      if (line.trim().toUpperCase(Locale.ROOT).equals("STOP")) return;
    }
  }

  private static void usage() {
    System.err.println("usage: FaultWorkerMain stream URL CORE RETENTION GENERATION | large URL CORE | readers URL CORE COUNT | embedded");
    System.exit(2);
  }
}
