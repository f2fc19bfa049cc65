package dev.prime.liberty;

import dev.prime.Block;
import java.util.List;

/**
 * A chain longer than one {@link RunSequences sequence of runs}: its sequences called in a
 * loop. Every part but the last has the full length, so the loop's call site sees at most two
 * classes and the JIT inlines them. No recursion: a chain of any length (100,000 blocks and
 * more) runs in a constant amount of stack.
 */
final class RunLoop implements Block<Object, Object> {
  private final Block<Object, Object>[] parts;

  /**
   * @param parts the sequences (and a last run), in order
   */
  RunLoop(List<Block<Object, Object>> parts) {
    @SuppressWarnings("unchecked")
    Block<Object, Object>[] array = (Block<Object, Object>[]) new Block<?, ?>[parts.size()];
    this.parts = parts.toArray(array);
  }

  @Override
  public Object process(Object input) {
    Object x = input;
    for (Block<Object, Object> part : parts) {
      x = part.process(x);
    }
    return x;
  }
}
