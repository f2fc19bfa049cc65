package dev.prime.conformance;

/**
 * The whole media conformance kit: a media runs every promise of docs/architecture.md ("What
 * every media keeps") with one small test class, e.g. {@code class LibertyConformanceTest implements
 * MediaConformance { public PrimeCore newCore(CoreConfig c) { return new LibertyCore(c); } }}.
 */
public interface MediaConformance
    extends ChainConformance,
        SourceConformance,
        TemplateConformance,
        ErrorConformance,
        LifecycleConformance,
        AwkwardConformance,
        TopologyConformance,
        ThrowableConformance,
        AtomicLinkConformance,
        ClaimRaceConformance,
        InterruptConformance,
        ValueCopyConformance,
        CodecFailureConformance,
        LongChainConformance,
        LoggingConformance,
        CombinatorConformance,
        RecordingConformance,
        MetricsConformance,
        LifecycleHookConformance,
        GenericServiceConformance,
        LinkVarianceConformance,
        MisuseConformance,
        ServiceInputConformance,
        TemplateFailureConformance,
        LongTemplateChainConformance,
        SameSourceTwiceConformance,
        ThreadNameConformance,
        RecordedKindsConformance,
        MeteredKindsConformance,
        ConcurrentDeclarationConformance,
        CoreReleaseConformance,
        BlockKindsConformance,
        UnusualNameConformance,
        FailedStartConformance {}
