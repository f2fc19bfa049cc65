package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.ValueCodec;
import java.util.List;
import java.util.concurrent.CopyOnWriteArrayList;
import org.junit.jupiter.api.Test;

/**
 * A codec that cannot decode a value it encoded (it breaks {@link ValueCodec}'s contract) does not
 * end the service that reads the value: as for a block that throws, the failure goes to the
 * core's {@link dev.prime.ErrorHandler} under the service's name, saying which service could not
 * decode a value with which codec, and the service goes on with the next value (architecture.md,
 * <i>Errors</i>: "A service never dies silently").
 */
public interface CodecFailureConformance extends ConformanceBase {

  /** The value {@link ForgetfulCodec} cannot read back. */
  int UNREADABLE = -1;

  /**
   * Copies through {@link #copyCodec()}, but its decode throws for {@link #UNREADABLE}: a codec
   * that cannot read its own encoding of one value.
   */
  final class ForgetfulCodec implements ValueCodec {
    private final ValueCodec codec;

    ForgetfulCodec(ValueCodec codec) {
      this.codec = codec;
    }

    @Override
    public byte[] encode(Object value) {
      return codec.encode(value);
    }

    @Override
    public Object decode(byte[] bytes) {
      Object value = codec.decode(bytes);
      if (Integer.valueOf(UNREADABLE).equals(value)) {
        throw new IllegalStateException("ForgetfulCodec forgot how to read " + UNREADABLE);
      }
      return value;
    }

    @Override
    public String toString() {
      return "ForgetfulCodec";
    }
  }

  /** One failure the error handler got. */
  record Failure(String service, Object input, Throwable error) {}

  @Test
  default void aValueItsCodecCannotDecodeGoesToTheErrorHandlerAndTheServiceGoesOn()
      throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder()
            .copyValues(new ForgetfulCodec(copyCodec()))
            .errorHandler((service, input, error) -> failures.add(new Failure(service, input, error)))
            .build();
    try (PrimeCore core = newCoreWithCodec(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("codec-input", events);
      Reader<Integer> tenfold = source.then(core.chain("tenfold", (Integer x) -> x * 10)).reader();
      core.start();
      events.publish(1);
      events.publish(UNREADABLE);
      events.publish(2);
      assertEquals(List.of(10, 20), takeOrFail(tenfold, 2), "the service went on");
      assertEquals(1, failures.size(), "failures reported: " + failures);
      Failure failure = failures.get(0);
      assertEquals("tenfold", failure.service(), "the service that could not decode the value");
      assertNotNull(failure.input(), "the input the handler gets is never null");
      String message = String.valueOf(failure.error().getMessage());
      assertTrue(message.contains("'tenfold'"), "names the service: " + failure.error());
      assertTrue(message.contains("ForgetfulCodec"), "names the codec: " + failure.error());
      Throwable cause = failure.error();
      while (cause != null && !(cause instanceof IllegalStateException)) {
        cause = cause.getCause();
      }
      assertNotNull(cause, "the codec's own exception is kept: " + failure.error());
    }
  }

  /**
   * What the error handler gets for a value the codec cannot decode is what {@link
   * dev.prime.ErrorHandler} says, on every media: a {@link PrimeException} whose cause is the
   * codec's own exception, and as the input the bytes that could not be decoded (a {@code
   * byte[]}; on Optimus the value's envelope).
   */
  @Test
  default void theHandlerGetsAPrimeExceptionCausedByTheCodecsAndTheBytes()
      throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder()
            .copyValues(new ForgetfulCodec(copyCodec()))
            .errorHandler((service, input, error) -> failures.add(new Failure(service, input, error)))
            .build();
    try (PrimeCore core = newCoreWithCodec(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("codec-bytes", events);
      Reader<Integer> doubled = source.then(core.chain("doubled", (Integer x) -> x * 2)).reader();
      core.start();
      events.publish(UNREADABLE);
      events.publish(4);
      assertEquals(8, takeOrFail(doubled), "the service went on");
      assertEquals(1, failures.size(), "failures reported: " + failures);
      Failure failure = failures.get(0);
      assertInstanceOf(PrimeException.class, failure.error(), "the error");
      assertInstanceOf(
          IllegalStateException.class, failure.error().getCause(), "its cause: " + failure.error());
      assertEquals(
          "ForgetfulCodec forgot how to read " + UNREADABLE,
          failure.error().getCause().getMessage(),
          "the codec's own exception");
      assertInstanceOf(byte[].class, failure.input(), "the input: the bytes not decoded");
    }
  }

  /**
   * {@link Reader}: a value the core's codec cannot decode is skipped (with a WARN line), and the
   * call goes on with the next value: a take, and a drain, which loses none of the values around
   * it.
   */
  @Test
  default void aReaderSkipsAValueItsCodecCannotDecodeAndLosesNoOther()
      throws InterruptedException {
    CoreConfig config = CoreConfig.builder().copyValues(new ForgetfulCodec(copyCodec())).build();
    try (PrimeCore core = newCoreWithCodec(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("codec-read", events);
      Reader<Integer> taken = source.reader();
      Reader<Integer> drained = source.reader();
      core.start();
      events.publish(1);
      events.publish(UNREADABLE);
      events.publish(2);
      events.publish(3);
      assertEquals(List.of(1, 2, 3), takeOrFail(taken, 3), "the values a take got");
      List<Integer> got = new java.util.ArrayList<>(drained.drain());
      if (got.size() < 3) { // a media that reads on the network may not have them all yet
        got.addAll(takeOrFail(drained, 3 - got.size()));
      }
      assertEquals(List.of(1, 2, 3), got, "the values a drain got");
    }
  }

  /**
   * A burst of values a reader cannot decode is logged as other bursts are (architecture.md,
   * <i>Values</i>): the first in full, the rest counted, not one WARN line per value.
   */
  @Test
  default void aBurstOfValuesAReaderCannotDecodeIsLoggedOnceThenCounted()
      throws InterruptedException {
    int unreadable = 50;
    List<String> lines;
    try (CapturedStderr err = new CapturedStderr()) {
      CoreConfig config = CoreConfig.builder().copyValues(new ForgetfulCodec(copyCodec())).build();
      try (PrimeCore core = newCoreWithCodec(config)) {
        EventBlock<Integer> events = new EventBlock<>();
        Reader<Integer> reader = core.source("unreadable-burst", events).reader();
        core.start();
        for (int i = 0; i < unreadable; i++) {
          events.publish(UNREADABLE);
        }
        events.publish(7);
        assertEquals(7, takeOrFail(reader), "the value after the burst");
      } // a count still owed is written when the core closes
      lines = err.lines();
    }
    List<String> mentions = lines.stream().filter(l -> l.contains("ForgetfulCodec")).toList();
    assertTrue(
        mentions.size() >= 1 && mentions.size() <= 4,
        "one WARN line and at most a few summaries, not "
            + mentions.size()
            + ":\n"
            + String.join("\n", mentions));
    assertEquals(
        unreadable,
        mentions.stream().mapToLong(l -> Math.max(1, CapturedStderr.summarised(l))).sum(),
        "the lines count every value skipped: " + mentions);
  }
}
