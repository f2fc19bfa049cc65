package dev.prime.mcap;

import java.util.Set;

/**
 * Where a chunk is (or, in a file without chunk indexes, one message outside chunks) and what it
 * holds, as far as the index says.
 *
 * @param startTime its earliest log time
 * @param offset the record's offset in the file
 * @param length the record's length, opcode and length prefix included
 * @param channelIds the channels it has messages of, or null if the index does not say
 * @param loneMessage whether the record is a Message outside chunks
 */
record ChunkRef(long startTime, long offset, long length, Set<Integer> channelIds, boolean loneMessage) {}
