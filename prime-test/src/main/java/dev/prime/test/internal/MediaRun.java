package dev.prime.test.internal;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.test.CoreSetup;
import dev.prime.test.Media;
import java.lang.reflect.Executable;
import java.lang.reflect.Method;
import java.lang.reflect.Parameter;
import java.time.Duration;
import java.util.List;
import java.util.Locale;
import java.util.concurrent.ThreadLocalRandom;
import java.util.concurrent.atomic.AtomicLong;
import java.util.function.Supplier;
import org.junit.jupiter.api.extension.AfterEachCallback;
import org.junit.jupiter.api.extension.BeforeEachCallback;
import org.junit.jupiter.api.extension.Extension;
import org.junit.jupiter.api.extension.ExtensionContext;
import org.junit.jupiter.api.extension.ParameterContext;
import org.junit.jupiter.api.extension.ParameterResolutionException;
import org.junit.jupiter.api.extension.ParameterResolver;
import org.junit.jupiter.api.extension.TestTemplateInvocationContext;

/**
 * One run of a {@code @PrimeTest} method on one media: its display name and the extension that
 * makes the run's core (before the {@code @BeforeEach} methods), injects it, and closes it after
 * the {@code @AfterEach} methods (on Optimus, then deletes its Redis keys).
 *
 * <p>Design note: JUnit makes one instance per run and calls it from the run's thread; the core
 * is still kept under a lock, so that a test that spreads its own threads over the callbacks
 * (parallel execution of other tests does not) cannot make two cores.
 */
final class MediaRun implements TestTemplateInvocationContext {
  /** Numbers every core this JVM's runs make, so that no two share a name (a Redis namespace). */
  private static final AtomicLong CORES = new AtomicLong();

  /**
   * Tells this JVM's core names from those of other test JVMs (parallel forks, earlier builds)
   * that use the same Redis ({@code prime.test.redis}).
   */
  private static final String JVM =
      Long.toString(ThreadLocalRandom.current().nextLong(36L * 36 * 36 * 36), 36);
  private static final int MAX_NAME = 64;

  private final Media media;
  private final Supplier<CoreSetup> setup;

  MediaRun(Media media, Supplier<CoreSetup> setup) {
    this.media = media;
    this.setup = setup;
  }

  @Override
  public String getDisplayName(int invocationIndex) {
    return media.displayName();
  }

  @Override
  public List<Extension> getAdditionalExtensions() {
    return List.of(new RunCore());
  }

  /** The core of one run. */
  private final class RunCore implements ParameterResolver, BeforeEachCallback, AfterEachCallback {
    private final Object lock = new Object();
    private PrimeCore core; // guarded by lock
    private boolean done; // guarded by lock

    @Override
    public void beforeEach(ExtensionContext context) {
      core(context);
    }

    @Override
    public void afterEach(ExtensionContext context) {
      PrimeCore made;
      synchronized (lock) {
        done = true;
        made = core;
      }
      if (made != null) {
        made.close();
        MediaCores.deleteKeys(media, made);
      }
    }

    @Override
    public boolean supportsParameter(ParameterContext parameter, ExtensionContext context) {
      Class<?> type = parameter.getParameter().getType();
      return type == Media.class
          || PrimeCore.class.isAssignableFrom(type)
          || type.getPackageName().equals(PrimeCore.class.getPackageName());
    }

    @Override
    public Object resolveParameter(ParameterContext parameter, ExtensionContext context) {
      Parameter p = parameter.getParameter();
      Class<?> type = p.getType();
      Executable executable = parameter.getDeclaringExecutable();
      String where = "parameter '" + p.getParameterizedType().getTypeName() + " " + p.getName()
          + "' of " + describe(executable);
      if (!(executable instanceof Method)) {
        throw new ParameterResolutionException(
            "@PrimeTest cannot inject " + where + ": a test instance may outlive one run, so the"
                + " core goes to the test method and its @BeforeEach/@AfterEach methods; take it"
                + " as a parameter there");
      }
      if (type == Media.class) {
        return media;
      }
      if (!PrimeCore.class.isAssignableFrom(type)) {
        throw new ParameterResolutionException(
            "@PrimeTest cannot inject " + where + ": it injects a PrimeCore (the run's core) and a"
                + " Media (the run's media). Make a " + type.getSimpleName()
                + " from the core in the test (core.chain(...), core.source(...), source.reader())");
      }
      PrimeCore made = core(context);
      if (!type.isInstance(made)) {
        throw new ParameterResolutionException(
            "@PrimeTest cannot inject " + where + " on " + media.displayName() + ": it wants a "
                + type.getSimpleName() + ", and this run's core is a "
                + made.getClass().getSimpleName() + ". Declare the parameter as PrimeCore, or run"
                + " only on the media it names (@PrimeTest(media = ...))");
      }
      return made;
    }

    /** The run's core, made on first use. */
    private PrimeCore core(ExtensionContext context) {
      synchronized (lock) {
        if (done) {
          throw new IllegalStateException(
              "the " + media.displayName() + " run of " + context.getDisplayName()
                  + " is over; its core is closed");
        }
        if (core == null) {
          core = make(context);
        }
        return core;
      }
    }

    private PrimeCore make(ExtensionContext context) {
      CoreSetup runSetup = setup.get();
      CoreConfig.Builder builder = CoreConfig.builder();
      runSetup.configure(media, builder);
      CoreConfig asked = builder.build();
      CoreConfig config = asked.toBuilder().name(runName(asked.name())).build();
      PrimeCore made =
          MediaCores.create(media, config, runSetup, () -> redisUrl(media, context));
      if (made == null || !config.name().equals(made.name())) {
        if (made != null) {
          made.close();
        }
        throw new IllegalStateException(
            runSetup.getClass().getName() + ".optimus(config, redisUrl) must make the core with"
                + " the config it is given (its name '" + config.name()
                + "' keeps this run's Redis keys apart from other runs'); it returned "
                + (made == null ? "null" : "a core named '" + made.name() + "'"));
      }
      return made;
    }

    /** {@code <base>-<media>-<n>-<jvm>}, cut to the longest core name. */
    private String runName(String asked) {
      String suffix = "-" + media.name().toLowerCase(Locale.ROOT).replace('_', '-') + "-"
          + CORES.incrementAndGet() + "-" + JVM;
      String base = asked == null ? "test" : asked;
      if (base.length() + suffix.length() > MAX_NAME) {
        base = base.substring(0, MAX_NAME - suffix.length());
      }
      return base + suffix;
    }
  }

  /**
   * The Redis URL of an Optimus run: the test class's Redis, or on {@link Media#OPTIMUS_SLOW_LINK}
   * the class's slow link in front of it, opened for its first such run.
   */
  private static String redisUrl(Media media, ExtensionContext context) {
    if (media != Media.OPTIMUS_SLOW_LINK) {
      return sharedRedis(context).url();
    }
    Duration delay =
        SlowLink.parseDelay(context.getConfigurationParameter(SlowLink.DELAY_PARAMETER).orElse(null));
    String redis = sharedRedis(context).url();
    return classStore(context)
        .getOrComputeIfAbsent(SlowLink.class, key -> SlowLink.open(redis, delay), SlowLink.class)
        .url();
  }

  /** The Redis of the test class that holds this run, started for its first Optimus run. */
  private static SharedRedis sharedRedis(ExtensionContext context) {
    String configured = context.getConfigurationParameter(PrimeTestExtension.REDIS_PARAMETER).orElse(null);
    return classStore(context)
        .getOrComputeIfAbsent(
            SharedRedis.class,
            key -> configured != null ? new SharedRedis(configured, null) : MediaCores.startEmbeddedRedis(),
            SharedRedis.class);
  }

  /** The store of the test class that holds this run: JUnit closes its values after the class. */
  private static ExtensionContext.Store classStore(ExtensionContext context) {
    ExtensionContext owner = context;
    while (owner.getTestMethod().isPresent() && owner.getParent().isPresent()) {
      owner = owner.getParent().get();
    }
    return owner.getStore(PrimeTestExtension.NAMESPACE);
  }

  private static String describe(Executable executable) {
    return executable.getDeclaringClass().getSimpleName() + "." + (executable instanceof Method
        ? executable.getName() : "<init>") + "()";
  }
}
