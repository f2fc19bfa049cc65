/**
 * Prime's core: the logic and topology API with the contract a media implements ({@code
 * dev.prime}), the topology model ({@code dev.prime.topology}) and helpers media build on the API
 * ({@code dev.prime.spi}). {@code dev.prime.internal} is exported to no module but Optimus (for
 * its rate-limited log and deadlines).
 */
@SuppressWarnings("module") // dev.prime.optimus is compiled after this module
module dev.prime {
  requires org.slf4j;

  exports dev.prime;
  exports dev.prime.spi;
  exports dev.prime.topology;
  exports dev.prime.internal to
      dev.prime.optimus;
}
