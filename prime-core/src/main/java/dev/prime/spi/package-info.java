/**
 * For media authors: the building blocks a {@link dev.prime.PrimeCore} implementation shares.
 * Users of Prime never need this package.
 */
package dev.prime.spi;
