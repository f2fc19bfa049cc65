/**
 * The workings of {@link dev.prime.test.PrimeTest}: not API. Only {@link LibertyCores}, {@link
 * RadiantCores} and {@link OptimusCores} name a media's classes, and they are loaded only when a
 * test runs on that media, so a project without a media's module never touches its classes.
 */
package dev.prime.test.internal;
