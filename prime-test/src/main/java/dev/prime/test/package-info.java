/**
 * Testing Prime topologies with JUnit 5: {@link dev.prime.test.PrimeTest} runs a test once per
 * media with a fresh core, and {@link dev.prime.test.ReaderAssert} checks what a reader emits,
 * waiting with timeouts instead of sleeps.
 *
 * <p>The media modules are optional dependencies of this module: add the ones your tests run on
 * ({@code dev.prime:prime-liberty}, {@code dev.prime:prime-radiant}, {@code
 * dev.prime:prime-optimus}) with test scope.
 */
package dev.prime.test;
