package dev.prime.faults;

import java.nio.charset.StandardCharsets;

/**
 * The Redis keys of an Optimus topology that the suite inspects or writes to from outside (to
 * count what is left behind, to push hostile entries): {@code prime:{<core name>}:<kind>:...}, as
 * Optimus derives them from the core and service names. Written down here independently of the
 * media's internal key class, on purpose: a change of the layout shows up as a failing fault test.
 */
final class TopologyKeys {
  private final String prefix;

  TopologyKeys(String coreName) {
    this.prefix = "prime:{" + coreName + "}:";
  }

  String serviceInput(String service) {
    return prefix + "svc:" + service + ":in";
  }

  /** The host lease of a service that has one host at a time: the id of the instance that runs it. */
  String hostLease(String service) {
    return prefix + "svc:" + service + ":host";
  }

  /** Host leases of the topology's services, as a SCAN pattern. */
  String hostLeases() {
    return prefix + "svc:*:host";
  }

  String sourceReaders(String source) {
    return prefix + "src:" + source + ":readers";
  }

  /** Reader lists of the topology (not services), as a SCAN pattern. */
  String readerLists() {
    return prefix + "rdr:*";
  }

  /** Reply lists of synchronous callers, as a SCAN pattern. */
  String replyLists() {
    return prefix + "reply:*";
  }

  String codec() {
    return prefix + "codec";
  }

  static byte[] bytes(String key) {
    return key.getBytes(StandardCharsets.UTF_8);
  }
}
