/**
 * The inspector: a live diagram page for a running core, served by the JDK's HTTP server (see
 * {@link dev.prime.inspector.PrimeInspector}). The jar's Automatic-Module-Name is {@code
 * dev.prime.inspector}; it needs the modules {@code dev.prime} and {@code jdk.httpserver}.
 */
package dev.prime.inspector;
