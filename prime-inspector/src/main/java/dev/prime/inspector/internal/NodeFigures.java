package dev.prime.inspector.internal;

/**
 * What the page shows under one box: how many values per second, how long one takes, how many
 * failed. A figure a source of figures does not have is {@code NaN} (latency) or {@code -1}
 * (counts), and the page shows a dash.
 *
 * @param rate values per second over the last sampling period
 * @param total values so far
 * @param latencyMillis mean processing time over the last period, in milliseconds, or NaN
 * @param errors failures so far, or -1
 */
public record NodeFigures(double rate, long total, double latencyMillis, long errors) {}
