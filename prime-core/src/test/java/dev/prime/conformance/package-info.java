/**
 * The media conformance kit, published in prime-core's test-jar. A media depends on it with
 * {@code <type>test-jar</type>} and runs every promise of docs/architecture.md ("What every media
 * keeps") with one class implementing {@link dev.prime.conformance.MediaConformance}. Each theme is one interface of default
 * {@code @Test} methods; the only overridable hooks are in {@link
 * dev.prime.conformance.ConformanceBase} (services per source link, whether blocks run on the
 * caller's thread, whether a publish before {@code start()} waits, the codec that copies values,
 * patience), each documented where it is declared.
 */
package dev.prime.conformance;
