package dev.prime;

import java.time.Duration;
import java.util.Objects;
import dev.prime.internal.RateLimitedLog;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * Settings shared by every media. Immutable; build one with {@link #builder()}.
 *
 * <pre>{@code
 * CoreConfig config = CoreConfig.builder()
 *     .name("robot")
 *     .sourceRetention(10_000)
 *     .errorHandler((service, input, error) -> alarms.raise(service, error))
 *     .build();
 * }</pre>
 */
public final class CoreConfig {

  /** Default number of values a source keeps for late or slow readers. */
  public static final int DEFAULT_SOURCE_RETENTION = 1024;

  /** Default time {@link PrimeCore#close()} waits for services to stop. */
  public static final Duration DEFAULT_SHUTDOWN_TIMEOUT = Duration.ofSeconds(5);

  /** Default time a publish waits for room in a full service input. */
  public static final Duration DEFAULT_PUBLISH_TIMEOUT = Duration.ofSeconds(10);

  private static final CoreConfig DEFAULTS = builder().build();

  private final String name;
  private final int sourceRetention;
  private final ErrorHandler errorHandler;
  private final Duration shutdownTimeout;
  private final Duration publishTimeout;
  private final ValueCodec valueCopies;
  private final PrimeClock clock;
  private final RecordingOptions recording;
  private final boolean metrics;

  private CoreConfig(Builder b) {
    this.name = b.name;
    this.sourceRetention = b.sourceRetention;
    this.errorHandler = b.errorHandler != null ? b.errorHandler : new LoggingErrorHandler();
    this.shutdownTimeout = b.shutdownTimeout;
    this.publishTimeout = b.publishTimeout;
    this.valueCopies = b.valueCopies;
    this.clock = b.clock;
    this.recording = b.recording;
    this.metrics = b.metrics;
  }

  /** {@return the default settings} */
  public static CoreConfig defaults() {
    return DEFAULTS;
  }

  /** {@return A builder starting from the defaults} */
  public static Builder builder() {
    return new Builder();
  }

  /**
   * {@return the core's name, used in thread names and log lines, or {@code null} for a
   * generated one ({@code liberty-1}, ...)}
   */
  public String name() {
    return name;
  }

  /**
   * {@return how many of its latest values each source keeps for readers that have not read them yet}
   */
  public int sourceRetention() {
    return sourceRetention;
  }

  /** {@return where the failures of asynchronous services go} */
  public ErrorHandler errorHandler() {
    return errorHandler;
  }

  /** {@return how long {@link PrimeCore#close()} waits for each group of services to stop} */
  public Duration shutdownTimeout() {
    return shutdownTimeout;
  }

  /**
   * {@return how long a publish waits for room in a full service input before it throws {@link
   * QueueFullException}} See {@link Builder#publishTimeout(Duration)}.
   */
  public Duration publishTimeout() {
    return publishTimeout;
  }

  /**
   * {@return the codec through which the in-memory media copy every value that crosses a
   * service boundary, or {@code null} (the default) if they pass values by reference} See
   * {@link Builder#copyValues(ValueCodec)}.
   */
  public ValueCodec valueCopies() {
    return valueCopies;
  }

  /**
   * {@return the clock the core's timers and samplers run on: {@link PrimeClock#system()} unless
   * {@link Builder#clock(PrimeClock)} set another}
   */
  public PrimeClock clock() {
    return clock;
  }

  /**
   * {@return how the core records what its sources publish and its chains return, or {@code
   * null} (the default) if it records nothing} See {@link Builder#recording(RecordingOptions)}.
   */
  public RecordingOptions recording() {
    return recording;
  }

  /**
   * {@return whether the core meters its services (off by default)} See {@link
   * Builder#metrics(boolean)}.
   */
  public boolean metrics() {
    return metrics;
  }

  /** {@return a builder starting from these settings} */
  public Builder toBuilder() {
    Builder b = new Builder();
    b.name = name;
    b.sourceRetention = sourceRetention;
    b.errorHandler = errorHandler;
    b.shutdownTimeout = shutdownTimeout;
    b.publishTimeout = publishTimeout;
    b.valueCopies = valueCopies;
    b.clock = clock;
    b.recording = recording;
    b.metrics = metrics;
    return b;
  }

  @Override
  public String toString() {
    return "CoreConfig[name=" + name + ", sourceRetention=" + sourceRetention
        + ", shutdownTimeout=" + shutdownTimeout
        + ", publishTimeout=" + publishTimeout
        + (valueCopies == null ? "" : ", copyValues=" + valueCopies)
        + (clock == PrimeClock.system() ? "" : ", clock=" + clock)
        + (recording == null ? "" : ", recording=" + recording)
        + (metrics ? ", metrics=on" : "") + "]";
  }

  /** Builds a {@link CoreConfig}. Not thread-safe. */
  public static final class Builder {
    private String name;
    private int sourceRetention = DEFAULT_SOURCE_RETENTION;
    private ErrorHandler errorHandler = null; // a LoggingErrorHandler of its own at build()
    private Duration shutdownTimeout = DEFAULT_SHUTDOWN_TIMEOUT;
    private Duration publishTimeout = DEFAULT_PUBLISH_TIMEOUT;
    private ValueCodec valueCopies;
    private PrimeClock clock = PrimeClock.system();
    private RecordingOptions recording;
    private boolean metrics;

    private Builder() {}

    /**
     * @param name 1 to 64 ASCII letters, digits, '.', '_' or '-'; {@code null} for a generated name
     * @return this builder
     * @throws IllegalArgumentException if {@code name} is not {@code null} and not such a name
     */
    public Builder name(String name) {
      if (name != null && !name.matches("[A-Za-z0-9._-]{1,64}")) {
        throw new IllegalArgumentException(
            "core name '" + name + "' is invalid: use 1 to 64 ASCII letters, digits, '.', '_' or '-'");
      }
      this.name = name;
      return this;
    }

    /**
     * How many of its latest values each source keeps for plain readers and collectors, which
     * skip (and count as missed) what falls out of it; on the in-memory media also how many
     * values a service's input holds before a publish waits for room (see {@link
     * #publishTimeout(Duration)}). The in-memory media keep it in a ring of that many slots that
     * each source (an event source or a service's output) allocates when it is declared, a
     * reference each: there a retention the heap cannot hold makes that declaration throw {@link
     * IllegalArgumentException}, changing nothing. A media that keeps sources outside the process
     * (Optimus: in Redis) allocates no ring.
     *
     * @param values how many values each source keeps, at least 1
     * @return this builder
     * @throws IllegalArgumentException if {@code values} is less than 1
     */
    public Builder sourceRetention(int values) {
      if (values < 1) {
        throw new IllegalArgumentException(
            "sourceRetention must be at least 1 value, was " + values);
      }
      this.sourceRetention = values;
      return this;
    }

    /**
     * The default handler logs a service's first failure with its stack trace, then at most one
     * WARN line per service every 10 s counting the others; after 10 s without failures the next
     * one is logged in full again.
     *
     * @param handler receives the failures of asynchronous services
     * @return this builder
     * @throws NullPointerException if {@code handler} is {@code null}
     */
    public Builder errorHandler(ErrorHandler handler) {
      this.errorHandler = Objects.requireNonNull(handler, "errorHandler must not be null");
      return this;
    }

    /**
     * @param timeout how long {@code close()} waits for services to stop; positive
     * @return this builder
     * @throws IllegalArgumentException if {@code timeout} is zero or negative
     * @throws NullPointerException if {@code timeout} is {@code null}
     */
    public Builder shutdownTimeout(Duration timeout) {
      Objects.requireNonNull(timeout, "shutdownTimeout must not be null");
      if (timeout.isNegative() || timeout.isZero()) {
        throw new IllegalArgumentException("shutdownTimeout must be positive, was " + timeout);
      }
      this.shutdownTimeout = timeout;
      return this;
    }

    /**
     * The longest a publish waits for room in a full service input (default 10 s). The input of
     * a service (a chain linked to a source, a filter, a flat-map, a listener) is a queue: a
     * publish never overwrites a value a service has not processed yet. When a service's input
     * holds as many unprocessed values as it can (the {@linkplain #sourceRetention source
     * retention} on the in-memory media, the queue limit on Optimus), the publish waits for the
     * service to take one; if none is taken within this time it throws {@link
     * QueueFullException} and publishes nothing. Plain {@link Reader}s never hold a publish up:
     * they skip what they missed.
     *
     * <p>On the in-memory media, values published before {@link PrimeCore#start()} wait in the
     * services' inputs; publishing more than they hold before the services run waits this long and
     * then fails (Optimus refuses a publish before the start at once). A service that
     * publishes into its own input (directly or through a cycle of services) waits for itself:
     * when its input is full that publish fails after this time, and the failure goes to the
     * error handler.
     *
     * @param timeout how long a publish waits for room; zero (fail at once) or positive
     * @return this builder
     * @throws IllegalArgumentException if {@code timeout} is negative
     * @throws NullPointerException if {@code timeout} is {@code null}
     */
    public Builder publishTimeout(Duration timeout) {
      Objects.requireNonNull(timeout, "publishTimeout must not be null");
      if (timeout.isNegative()) {
        throw new IllegalArgumentException(
            "publishTimeout must be zero or positive, was " + timeout);
      }
      this.publishTimeout = timeout;
      return this;
    }

    /**
     * Makes the in-memory media copy every value that crosses a service boundary through
     * {@code codec}, as a distributed media must: a value published to a source (each reader
     * gets a copy of its own), a source-linked service's input and output, and a synchronous
     * call's input and result. Values are to be treated as immutable; with this option a test on
     * Liberty or Radiant fails the way Optimus would, when a value is mutated after it was handed
     * over (the receiver does not see the change) or when its type is one the codec refuses
     * ({@link IllegalArgumentException} at the publish or the call). Meant for tests: copying costs
     * an encode and a decode per value. Chains linked together are one service on the in-memory
     * media, and so are a template and its parts, so values between them are not copied. Optimus
     * copies every value through its own codec whatever this says.
     *
     * <pre>{@code
     * new LibertyCore(CoreConfig.builder().copyValues(KryoCodec.standard()).build())
     * }</pre>
     *
     * @param codec copies the values; {@code null} to pass values by reference (the default)
     * @return this builder
     */
    public Builder copyValues(ValueCodec codec) {
      this.valueCopies = codec;
      return this;
    }

    /**
     * Sets the clock the core's timers ({@link PrimeCore#timer}) and samplers ({@link
     * Source#sample}) run on. The default is {@link PrimeClock#system()}; a {@link VirtualClock}
     * makes them tick only as a test advances it, fast and the same every run.
     *
     * @param clock the clock
     * @return this builder
     * @throws NullPointerException if {@code clock} is {@code null}
     */
    public Builder clock(PrimeClock clock) {
      this.clock = Objects.requireNonNull(clock, "clock must not be null");
      return this;
    }

    /**
     * Turns recording on: the core records every value each of its event sources ({@link
     * PrimeCore#source(String, EventBlock)}) publishes and each of its chains made of a block
     * ({@link PrimeCore#chain(String, Block)}) returns, with time stamps, in a ring per name (only
     * those: filters, flat-maps, listeners, templates and other services are not recorded, see
     * {@link Recording}); read it with
     * {@link PrimeCore#recording()}. Off by default, and then free: no recording code is compiled
     * into any chain or subscribed to any source.
     *
     * <pre>{@code
     * new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(10_000)).build())
     * }</pre>
     *
     * @param options the ring size and read timeout; {@code null} to record nothing (the default)
     * @return this builder
     */
    public Builder recording(RecordingOptions options) {
      this.recording = options;
      return this;
    }

    /**
     * Turns metrics on: the core counts, for every chain, service and event source of its diagram
     * that runs logic, the values in and out, failures and the time per value, and reads the
     * media's dead letters and queue depths; read them with {@link PrimeCore#metrics()} (see
     * {@link Metrics}). Off by default, and then free: no metering code is compiled into any
     * chain or service, nor subscribed to any source.
     *
     * <pre>{@code
     * new LibertyCore(CoreConfig.builder().metrics(true).build())
     * }</pre>
     *
     * @param on whether to meter
     * @return this builder
     */
    public Builder metrics(boolean on) {
      this.metrics = on;
      return this;
    }

    /** {@return the settings} */
    public CoreConfig build() {
      return new CoreConfig(this);
    }
  }

  /** Writes the failure counts the default error handler still owes (a core closes). */
  void flushErrorSummaries() {
    if (errorHandler instanceof LoggingErrorHandler logging) {
      logging.bursts.flush();
    }
  }

  /**
   * The default error handler: logs the first failure of a service in a burst with its stack
   * trace, then at most one WARN line per service every 10 s counting the others; after 10 s
   * without failures a service's next failure is logged in full again. One per {@link CoreConfig},
   * so its state is bounded by the core's services.
   */
  private static final class LoggingErrorHandler implements ErrorHandler {
    private static final Logger LOG = LoggerFactory.getLogger(ErrorHandler.class);
    private final RateLimitedLog bursts = new RateLimitedLog(ErrorHandler.class.getName());

    @Override
    public void handle(String service, Object input, Throwable error) {
      String inputType = input == null ? "null" : input.getClass().getName();
      bursts.record(
          "service '" + service + "' failed",
          1,
          error.toString(),
          () ->
              LOG.error(
                  "service '{}' failed on a {}; going on with the next value (further failures"
                      + " of this service are counted, at most one line per {} s)",
                  service,
                  inputType,
                  RateLimitedLog.DEFAULT_SECONDS,
                  error));
    }
  }
}
