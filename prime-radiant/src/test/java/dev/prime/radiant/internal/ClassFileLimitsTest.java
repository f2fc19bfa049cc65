package dev.prime.radiant.internal;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Tuple5;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.FutureTask;
import java.util.concurrent.TimeUnit;
import java.util.function.Predicate;
import net.bytebuddy.jar.asm.ClassReader;
import org.junit.jupiter.api.Test;

/**
 * Every class the compiler writes stays within the JVM's limits, whatever the tree: no
 * {@code process} method over HotSpot's {@code HugeMethodLimit} (8000 bytes, above which a method
 * is never JIT-compiled), whatever the shape of the links (left-nested as {@code then} builds
 * them, right-nested, or deep nests of templates), and every leaf has a distinct chain name (the
 * worst case for the failure handlers). Trees are built here as nodes, without a core.
 */
class ClassFileLimitsTest {
  /** HotSpot's {@code -XX:HugeMethodLimit} default. */
  private static final int HUGE_METHOD_LIMIT = 8000;

  private static final Block<Long, Long> PLUS_ONE = x -> x + 1;
  private static final Predicate<Long> NOT_NEGATIVE = x -> x >= 0;

  /** What one compilation wrote: per class file, the code length of each method, by name. */
  private final List<Map<String, Integer>> classes = new ArrayList<>();

  private Block<Object, Object> compile(Node root) throws Exception {
    FutureTask<Block<Object, Object>> task =
        new FutureTask<>(() -> FusedCompiler.compile("limits", root, b -> classes.add(code(b))));
    Thread thread = new Thread(task, "default-stack");
    thread.start();
    try {
      return task.get(300, TimeUnit.SECONDS);
    } catch (ExecutionException e) {
      throw new AssertionError("compiling failed on a default stack", e.getCause());
    } finally {
      thread.join(10_000);
    }
  }

  private static Node leaf(int i) {
    return new Node.Leaf("chain-" + i, PLUS_ONE);
  }

  private void assertWithinLimits(int expectedClassesAtLeast) {
    assertTrue(
        classes.size() >= expectedClassesAtLeast,
        "classes written: " + classes.size() + ", expected at least " + expectedClassesAtLeast);
    int largest = 0;
    for (Map<String, Integer> methods : classes) {
      for (Map.Entry<String, Integer> method : methods.entrySet()) {
        largest = Math.max(largest, method.getValue());
        assertTrue(
            method.getValue() < HUGE_METHOD_LIMIT,
            method.getKey() + " has " + method.getValue() + " bytes of bytecode");
      }
    }
    assertTrue(largest > 1000, "segments are filled, largest method: " + largest + " bytes");
  }

  @Test
  void aLeftNestedChainOfOneHundredThousandLinks() throws Exception {
    Node root = leaf(0);
    for (int i = 1; i < 100_000; i++) {
      root = new Node.Link(root, leaf(i));
    }
    assertEquals(100_000L + 5, compile(root).process(5L));
    assertWithinLimits(100_000 / FusedCompiler.MAX_SITES);
  }

  @Test
  void aRightNestedChainOfOneHundredThousandLinks() throws Exception {
    Node root = leaf(99_999);
    for (int i = 99_998; i >= 0; i--) {
      root = new Node.Link(leaf(i), root);
    }
    assertEquals(100_000L, compile(root).process(0L));
    assertWithinLimits(100_000 / FusedCompiler.MAX_SITES);
  }

  @Test
  void tenThousandNestedGuardsAndIfs() throws Exception {
    Node root = leaf(0);
    for (int i = 1; i <= 10_000; i++) {
      root =
          i % 2 == 0
              ? new Node.Guard("guard-" + i, NOT_NEGATIVE, new Node.Link(root, leaf(i)), PLUS_ONE)
              : new Node.IfElse("if-" + i, NOT_NEGATIVE, new Node.Link(root, leaf(i)), leaf(-i));
    }
    assertEquals(10_001L, compile(root).process(0L));
    assertWithinLimits(10_000 * 3 / FusedCompiler.MAX_SITES); // 3 sites a level
  }

  @Test
  void unionsOfLongChainsNestedInForEach() throws Exception {
    List<Node> parts = new ArrayList<>();
    int partLength = 3_000;
    for (int p = 0; p < 5; p++) {
      Node part = leaf(p * partLength);
      for (int i = 1; i < partLength; i++) {
        part = new Node.Link(part, leaf(p * partLength + i));
      }
      parts.add(part);
    }
    Node root = new Node.ForEach("each", new Node.Union("union", parts));
    @SuppressWarnings("unchecked")
    List<Tuple5<Long, Long, Long, Long, Long>> out =
        (List<Tuple5<Long, Long, Long, Long, Long>>) compile(root).process(List.of(1L, 2L));
    assertEquals(3_001L, out.get(0).first());
    assertEquals(3_002L, out.get(1).fifth());
    assertWithinLimits(5 * partLength / FusedCompiler.MAX_SITES);
  }

  /** Method name and descriptor to code length, read from a class file. */
  private static Map<String, Integer> code(byte[] classFile) {
    ClassReader reader = new ClassReader(classFile);
    assertTrue(reader.getItemCount() < 65_535, "constant pool entries: " + reader.getItemCount());
    char[] buffer = new char[reader.getMaxStringLength()];
    int offset = reader.header + 6;
    offset += 2 + 2 * reader.readUnsignedShort(offset); // interfaces
    offset = skipMembers(reader, offset, buffer, null);
    Map<String, Integer> methods = new HashMap<>();
    skipMembers(reader, offset, buffer, methods);
    return methods;
  }

  /** Skips fields or methods; records the code length of methods when {@code code} is given. */
  private static int skipMembers(
      ClassReader reader, int offset, char[] buffer, Map<String, Integer> code) {
    int count = reader.readUnsignedShort(offset);
    offset += 2;
    for (int m = 0; m < count; m++) {
      String name = reader.readUTF8(offset + 2, buffer);
      int attributes = reader.readUnsignedShort(offset + 6);
      offset += 8;
      for (int a = 0; a < attributes; a++) {
        String attribute = reader.readUTF8(offset, buffer);
        int length = reader.readInt(offset + 2);
        if (code != null && attribute.equals("Code")) {
          code.put(reader.getClassName() + "." + name, reader.readInt(offset + 6 + 4));
        }
        offset += 6 + length;
      }
    }
    return offset;
  }
}
