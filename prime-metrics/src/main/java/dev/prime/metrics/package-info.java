/**
 * A Prime core's metrics as Micrometer meters: {@link dev.prime.metrics.PrimeMetrics}, a {@code
 * MeterBinder} whose meters are named {@code prime.service.*} and tagged with the topology's
 * service names. An optional module, so that the core stays free of dependencies.
 */
package dev.prime.metrics;
