package dev.prime.conformance;

/**
 * The whole media conformance kit: a media runs every semantic of DESIGN.md ("Semantics every
 * media must keep") with one small test class, e.g. {@code class LibertyConformanceTest implements
 * MediaConformance { public PrimeCore newCore(CoreConfig c) { return new LibertyCore(c); } }}.
 */
public interface MediaConformance
    extends ChainConformance,
        SourceConformance,
        TemplateConformance,
        ErrorConformance,
        LifecycleConformance,
        AwkwardConformance,
        ThrowableConformance,
        AtomicLinkConformance,
        InterruptConformance,
        ValueCopyConformance,
        LongChainConformance {}
