package dev.prime.mcap;

import java.util.ArrayList;
import java.util.Comparator;
import java.util.Iterator;
import java.util.List;
import java.util.NoSuchElementException;
import java.util.PriorityQueue;
import java.util.function.Function;

/**
 * The messages of many chunks in log-time order: a k-way merge over the chunks sorted by start
 * time, loading a chunk only once the merge reaches its start time, so at once only the chunks
 * that overlap in time are in memory. Equal times come in file order.
 */
final class LogTimeMerge implements Iterator<McapMessage> {
  private final List<ChunkRef> order;
  private final Function<ChunkRef, List<McapMessage>> load;
  private int nextChunk;
  private final PriorityQueue<Cursor> heap = new PriorityQueue<>(
      Comparator.comparingLong((Cursor c) -> c.current().logTime()).thenComparingLong(c -> c.rank));

  private static final class Cursor {
    final List<McapMessage> messages;
    final long rank;
    int index;

    Cursor(List<McapMessage> messages, long rank) {
      this.messages = messages;
      this.rank = rank;
    }

    McapMessage current() {
      return messages.get(index);
    }
  }

  /**
   * @param chunks every chunk of the file
   * @param channelId the one channel wanted, or null for all: chunks the index says have none of
   *     its messages are skipped
   * @param load a chunk's wanted messages, sorted by log time
   */
  LogTimeMerge(List<ChunkRef> chunks, Integer channelId, Function<ChunkRef, List<McapMessage>> load) {
    this.load = load;
    List<ChunkRef> wanted = new ArrayList<>();
    for (ChunkRef ref : chunks) {
      if (channelId == null || ref.channelIds() == null || ref.channelIds().contains(channelId)) {
        wanted.add(ref);
      }
    }
    wanted.sort(Comparator.comparingLong(ChunkRef::startTime).thenComparingLong(ChunkRef::offset));
    this.order = wanted;
  }

  private void fill() {
    while (nextChunk < order.size()
        && (heap.isEmpty() || order.get(nextChunk).startTime() <= heap.peek().current().logTime())) {
      ChunkRef ref = order.get(nextChunk++);
      List<McapMessage> messages = load.apply(ref);
      if (!messages.isEmpty()) {
        heap.add(new Cursor(messages, ref.offset()));
      }
    }
  }

  @Override
  public boolean hasNext() {
    fill();
    return !heap.isEmpty();
  }

  @Override
  public McapMessage next() {
    if (!hasNext()) {
      throw new NoSuchElementException();
    }
    Cursor cursor = heap.poll();
    McapMessage message = cursor.current();
    cursor.index++;
    if (cursor.index < cursor.messages.size()) {
      heap.add(cursor);
    }
    return message;
  }
}
