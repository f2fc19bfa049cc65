package dev.prime.faults;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import java.nio.ByteBuffer;

/**
 * The topologies the test process and its worker JVMs both declare (same names, so they agree on
 * every Redis key):
 *
 * <ul>
 *   <li>{@link #declareStream}: source {@code ids} (ids as {@code Long}) through service
 *       {@code stamp}, which marks each id with the generation of the process that ran it;
 *   <li>{@link #declareLarge}: source {@code blobs} (byte arrays whose first 8 bytes are their
 *       sequence number) through service {@code measure} (returns that number); and chain
 *       {@code size}, called synchronously.
 * </ul>
 *
 * The observing (test) process reads the output with a {@link Reader}, as a user would, and feeds
 * a {@link Ledger} from it ({@link LedgerFeed}). What is counted is therefore what a reader
 * receives: a service may run a value again after a crash (at-least-once processing), and only
 * duplicates that reach readers count.
 */
final class StreamTopology {
  /** A stamped value is {@code generation * GENERATION + id}. */
  static final long GENERATION = 1_000_000_000L;

  /** A retention no test reaches, for tests that are not about retention. */
  static final int WIDE_RETENTION = 1_000_000;

  private StreamTopology() {}

  /** The declared stream topology: its output, and a reader of it if asked for. */
  record Stream(Source<Long> output, Reader<Long> observer) {}

  /** The declared large-value topology: the {@code size} chain's block, and a reader of {@code measure}'s output if asked for. */
  record Large(Block<byte[], Integer> size, Reader<Long> observer) {}

  /** Declares the stream topology; {@code stamp} marks with {@code generation}; {@code observe}: make a reader of the output. */
  static Stream declareStream(PrimeCore core, EventBlock<Long> ids, int generation, boolean observe) {
    Source<Long> stamped = core.source("ids", ids).then(core.<Long, Long>chain("stamp", id -> generation * GENERATION + id));
    return new Stream(stamped, observe ? stamped.reader() : null);
  }

  /** Declares the large-value topology; {@code observe}: make a reader of {@code measure}'s output. */
  static Large declareLarge(PrimeCore core, EventBlock<byte[]> blobs, boolean observe) {
    Source<Long> measured = core.source("blobs", blobs).then(core.<byte[], Long>chain("measure", StreamTopology::sequenceOf));
    Reader<Long> observer = observe ? measured.reader() : null;
    return new Large(core.<byte[], Integer>chain("size", blob -> blob.length).toBlock(), observer);
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
}
