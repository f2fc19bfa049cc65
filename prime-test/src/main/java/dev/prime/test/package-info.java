/**
 * Testing Prime topologies with JUnit 5: {@link dev.prime.test.PrimeTest} runs a test once per
 * media with a fresh core, and {@link dev.prime.test.ReaderAssert} checks what a reader emits,
 * waiting with timeouts instead of sleeps.
 *
 * <p>The media modules are optional dependencies of this module: add the ones your tests run on
 * ({@code dev.prime:prime-liberty}, {@code dev.prime:prime-radiant}, {@code
 * dev.prime:prime-optimus}) with test scope.
 *
 * <p>JUnit: Jupiter 5.10 to 5.14. On each, what a test class's Optimus runs share (the class's
 * embedded Redis, the slow link in front of it) is stopped when the class ends, also on a JUnit
 * before 5.13, which closes no {@code AutoCloseable} value of an extension store.
 */
package dev.prime.test;
