package dev.prime.faults;

import java.util.ArrayList;
import java.util.HashSet;
import java.util.List;
import java.util.Set;
import redis.clients.jedis.Jedis;
import redis.clients.jedis.params.ScanParams;
import redis.clients.jedis.resps.ScanResult;

/** What a core may leave behind, counted from outside: its threads, its Redis connections, keys. */
final class Leftovers {
  private static final int MAX_SCAN_ROUNDS = 100_000;

  private Leftovers() {}

  /** Live threads of this JVM named {@code prime-<core>-...}. */
  static List<String> threadsOf(String coreName) {
    List<String> names = new ArrayList<>();
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      if (thread.isAlive() && thread.getName().startsWith("prime-" + coreName + "-")) names.add(thread.getName());
    }
    return names;
  }

  /** Connections Redis lists (CLIENT LIST) under the client names of {@code coreName}. */
  static long clientsOf(Jedis jedis, String coreName) {
    return jedis.clientList().lines()
        .filter(line -> line.contains(" name=prime-" + coreName + " ") || line.contains(" name=prime-" + coreName + "-"))
        .count();
  }

  /** Keys matching {@code pattern} (SCAN, bounded in rounds). */
  static Set<String> keys(Jedis jedis, String pattern) {
    Set<String> keys = new HashSet<>();
    String cursor = ScanParams.SCAN_POINTER_START;
    ScanParams params = new ScanParams().match(pattern).count(1000);
    for (int round = 0; round < MAX_SCAN_ROUNDS; round++) {
      ScanResult<String> page = jedis.scan(cursor, params);
      keys.addAll(page.getResult());
      cursor = page.getCursor();
      if (cursor.equals(ScanParams.SCAN_POINTER_START)) return keys;
    }
    throw new IllegalStateException("SCAN " + pattern + " did not finish in " + MAX_SCAN_ROUNDS + " rounds");
  }
}
