/**
 * The inspector: a live diagram page for a running core, served by the JDK's HTTP server
 * ({@link dev.prime.inspector.PrimeInspector}). {@code dev.prime.inspector.internal} is not
 * exported.
 */
module dev.prime.inspector {
  requires transitive dev.prime;
  requires jdk.httpserver;

  exports dev.prime.inspector;
}
