package dev.prime.mcap;

import java.net.InetAddress;
import java.net.UnknownHostException;
import java.util.LinkedHashMap;
import java.util.Map;

/**
 * The process that writes a recording: its host name and pid, so that the files of the processes
 * of one topology, merged, still say which process recorded what.
 *
 * @param host the host name ({@code HOSTNAME}, else the local host's name, else {@code unknown})
 * @param pid the process id
 * @param start when the process started (ISO-8601), or empty if the OS does not say
 */
record ProcessIdentity(String host, long pid, String start) {

  static ProcessIdentity current() {
    ProcessHandle self = ProcessHandle.current();
    return new ProcessIdentity(
        hostName(), self.pid(), self.info().startInstant().map(Object::toString).orElse(""));
  }

  /** {@return {@code pid@host}} */
  String id() {
    return pid + "@" + host;
  }

  /** {@return the Metadata record's pairs} */
  Map<String, String> metadata() {
    Map<String, String> pairs = new LinkedHashMap<>();
    pairs.put("host", host);
    pairs.put("pid", Long.toString(pid));
    if (!start.isEmpty()) {
      pairs.put("process_start", start);
    }
    return pairs;
  }

  private static String hostName() {
    String fromEnvironment = System.getenv("HOSTNAME");
    if (fromEnvironment != null && !fromEnvironment.isBlank()) {
      return fromEnvironment.strip();
    }
    try {
      return InetAddress.getLocalHost().getHostName();
    } catch (UnknownHostException e) {
      return "unknown";
    }
  }
}
