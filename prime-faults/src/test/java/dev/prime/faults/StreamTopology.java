package dev.prime.faults;

import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Source;
import java.nio.ByteBuffer;
import java.util.concurrent.atomic.AtomicReference;

/**
 * The topologies the test process and its worker JVMs both declare (same names, same order, so
 * they agree on every Redis key):
 *
 * <ul>
 *   <li>{@link #declareStream}: source {@code ids} (ids as {@code Long}) through service
 *       {@code stamp} (a worker marks each id with its generation) into service {@code collect},
 *       which hands every arrival to the current {@link Ledger} of the test process.
 *   <li>{@link #declareLarge}: source {@code blobs} (byte arrays whose first 8 bytes are their
 *       sequence number) through service {@code measure} (returns that number) into
 *       {@code collect}; and chain {@code size}, called synchronously.
 * </ul>
 */
final class StreamTopology {
  /** A stamped value is {@code generation * GENERATION + id}. */
  static final long GENERATION = 1_000_000_000L;

  /** A retention no test reaches, for tests that are not about retention. */
  static final int WIDE_RETENTION = 1_000_000;

  private StreamTopology() {}

  /** Declares the stream topology; {@code stamp} marks with {@code generation}, {@code collect} feeds {@code ledger}. */
  static Source<Long> declareStream(PrimeCore core, EventBlock<Long> ids, int generation, AtomicReference<Ledger> ledger) {
    Source<Long> stamped = core.source("ids", ids).then(core.<Long, Long>chain("stamp", id -> generation * GENERATION + id));
    collect(core, stamped, ledger);
    return stamped;
  }

  /** Declares the large-value topology; returns the synchronous {@code size} chain's block. */
  static dev.prime.Block<byte[], Integer> declareLarge(PrimeCore core, EventBlock<byte[]> blobs, AtomicReference<Ledger> ledger) {
    Source<Long> measured = core.source("blobs", blobs).then(core.<byte[], Long>chain("measure", StreamTopology::sequenceOf));
    collect(core, measured, ledger);
    return core.<byte[], Integer>chain("size", blob -> blob.length).toBlock();
  }

  /** A blob of {@code bytes} bytes carrying {@code sequence} in its first 8 bytes. */
  static byte[] blob(long sequence, int bytes) {
    byte[] blob = new byte[bytes];
    ByteBuffer.wrap(blob).putLong(sequence);
    blob[bytes - 1] = (byte) sequence;
    return blob;
  }

  private static long sequenceOf(byte[] blob) {
    return ByteBuffer.wrap(blob).getLong();
  }

  private static void collect(PrimeCore core, Source<Long> values, AtomicReference<Ledger> ledger) {
    values.then(core.<Long, Long>chain("collect", value -> {
      Ledger current = ledger.get();
      if (current != null) current.arrived(value % GENERATION, (int) (value / GENERATION));
      return null; // publishes nothing
    }));
  }
}
