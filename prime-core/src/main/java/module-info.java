/**
 * Prime's core: the logic and topology API ({@code dev.prime}), the topology model ({@code
 * dev.prime.topology}), the templates' logic blocks ({@code dev.prime.blocks}) and the media SPI
 * ({@code dev.prime.spi}). {@code dev.prime.internal} is not exported.
 */
module dev.prime {
  requires org.slf4j;

  exports dev.prime;
  exports dev.prime.spi;
  exports dev.prime.topology;
}
