package dev.prime;

import dev.prime.spi.ValueCodec;
import java.time.Duration;
import java.util.Objects;
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

  private static final CoreConfig DEFAULTS = builder().build();

  private final String name;
  private final int sourceRetention;
  private final ErrorHandler errorHandler;
  private final Duration shutdownTimeout;
  private final ValueCodec valueCopies;

  private CoreConfig(Builder b) {
    this.name = b.name;
    this.sourceRetention = b.sourceRetention;
    this.errorHandler = b.errorHandler;
    this.shutdownTimeout = b.shutdownTimeout;
    this.valueCopies = b.valueCopies;
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
   * {@return the codec through which the in-memory media copy every value that crosses a
   * service boundary, or {@code null} (the default) if they pass values by reference} See
   * {@link Builder#copyValues(ValueCodec)}.
   */
  public ValueCodec valueCopies() {
    return valueCopies;
  }

  /** {@return a builder starting from these settings} */
  public Builder toBuilder() {
    Builder b = new Builder();
    b.name = name;
    b.sourceRetention = sourceRetention;
    b.errorHandler = errorHandler;
    b.shutdownTimeout = shutdownTimeout;
    b.valueCopies = valueCopies;
    return b;
  }

  @Override
  public String toString() {
    return "CoreConfig[name=" + name + ", sourceRetention=" + sourceRetention
        + ", shutdownTimeout=" + shutdownTimeout
        + (valueCopies == null ? "" : ", copyValues=" + valueCopies) + "]";
  }

  /** Builds a {@link CoreConfig}. Not thread-safe. */
  public static final class Builder {
    private String name;
    private int sourceRetention = DEFAULT_SOURCE_RETENTION;
    private ErrorHandler errorHandler = LoggingErrorHandler.INSTANCE;
    private Duration shutdownTimeout = DEFAULT_SHUTDOWN_TIMEOUT;
    private ValueCodec valueCopies;

    private Builder() {}

    /**
     * @param name letters, digits, '.', '_' or '-'; {@code null} for a generated name
     * @return this builder
     */
    public Builder name(String name) {
      if (name != null && !name.matches("[A-Za-z0-9._-]{1,64}")) {
        throw new IllegalArgumentException(
            "core name '" + name + "' is invalid: use 1 to 64 letters, digits, '.', '_' or '-'");
      }
      this.name = name;
      return this;
    }

    /**
     * @param values how many values each source keeps, at least 1
     * @return this builder
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
     * @param handler receives the failures of asynchronous services
     * @return this builder
     */
    public Builder errorHandler(ErrorHandler handler) {
      this.errorHandler = Objects.requireNonNull(handler, "errorHandler must not be null");
      return this;
    }

    /**
     * @param timeout how long {@code close()} waits for services to stop; positive
     * @return this builder
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
     * Makes the in-memory media copy every value that crosses a service boundary through
     * {@code codec}, as a distributed media must: a value published to a source (each reader
     * gets a copy of its own), a source-linked service's input and output, and a synchronous
     * call's input and result. Values are to be treated as immutable; with this option a test on
     * Liberty or Radiant fails the way Optimus would, when a value is mutated after it was handed
     * over (the receiver does not see the change) or when its type is one the codec refuses
     * ({@link IllegalArgumentException} at the publish or the call). Meant for tests: copying costs
     * an encode and a decode per value. Chains linked together are one service on the in-memory
     * media, so values between them are not copied. Optimus copies every value through its own
     * codec whatever this says.
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

    /** {@return the settings} */
    public CoreConfig build() {
      return new CoreConfig(this);
    }
  }

  /** The default error handler: log the failure and go on. */
  private enum LoggingErrorHandler implements ErrorHandler {
    INSTANCE;

    private static final Logger LOG = LoggerFactory.getLogger(ErrorHandler.class);

    @Override
    public void handle(String service, Object input, Throwable error) {
      LOG.error(
          "service '{}' failed on a {}; going on with the next value",
          service,
          input.getClass().getName(),
          error);
    }
  }
}
