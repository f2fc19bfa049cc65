package dev.prime.radiant.internal;

import dev.prime.Block;
import dev.prime.EventBlock;
import java.lang.reflect.Modifier;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Deque;
import java.util.IdentityHashMap;
import java.util.List;
import java.util.Map;
import java.util.function.Predicate;

/**
 * The static fields of a fused class: one per distinct object the chain calls, typed with the
 * object's own class when the generated class can name it (public, not hidden, exported, and
 * resolved to the same class by the generated class's loader: Prime's classes, the user's classes
 * Prime's loader sees, and the other classes of the same chain), else with the interface it is
 * called through.
 */
final class ConstantFields {

  /**
   * One field.
   *
   * @param name field name
   * @param type declared type
   * @param value what it holds
   */
  record Field(String name, Class<?> type, Object value) {
    boolean viaInterface() {
      return type.isInterface();
    }
  }

  private final ClassLoader resolving;
  private final List<Field> fields = new ArrayList<>();
  private final Map<Object, Field> blocks = new IdentityHashMap<>();
  private final Map<Object, Field> predicates = new IdentityHashMap<>();
  private final Map<Object, Field> events = new IdentityHashMap<>();

  private ConstantFields(ClassLoader resolving) {
    this.resolving = resolving;
  }

  /**
   * Lays out the fields for every constant in a tree.
   *
   * @param root the tree
   * @param resolving the loader of the generated class
   * @return the layout
   */
  static ConstantFields of(Node root, ClassLoader resolving) {
    ConstantFields layout = new ConstantFields(resolving);
    layout.collect(root);
    return layout;
  }

  List<Field> all() {
    return fields;
  }

  Field block(Block<?, ?> block) {
    return blocks.computeIfAbsent(block, b -> add("block", b, Block.class));
  }

  Field predicate(Predicate<?> predicate) {
    return predicates.computeIfAbsent(
        predicate, p -> add("predicate", p, Predicate.class));
  }

  Field events(EventBlock<?> target) {
    return events.computeIfAbsent(target, e -> add("events", e, EventBlock.class));
  }

  private Field add(String role, Object value, Class<?> fallback) {
    Class<?> own = value.getClass();
    Class<?> type = nameable(own) ? own : fallback;
    Field field = new Field(role + fields.size(), type, value);
    fields.add(field);
    return field;
  }

  private boolean nameable(Class<?> type) {
    if (type.isHidden() || type.isSynthetic() || !Modifier.isPublic(type.getModifiers())) {
      return false;
    }
    Module module = type.getModule();
    if (module.isNamed() && !module.isExported(type.getPackageName())) {
      return false;
    }
    try {
      return Class.forName(type.getName(), false, resolving) == type;
    } catch (ClassNotFoundException | LinkageError notVisible) {
      return false;
    }
  }

  /** Visits the tree in pre-order (the fields' order), with an explicit stack. */
  private void collect(Node root) {
    Deque<Node> pending = new ArrayDeque<>();
    pending.push(root);
    while (!pending.isEmpty()) {
      Node node = pending.pop();
      collectOwn(node);
      List<Node> children = node.children();
      for (int i = children.size() - 1; i >= 0; i--) {
        pending.push(children.get(i));
      }
    }
  }

  private void collectOwn(Node node) {
    if (node instanceof Node.Leaf leaf) {
      block(leaf.block());
    } else if (node instanceof Node.Opaque opaque) {
      block(opaque.block());
    } else if (node instanceof Node.IfElse branch) {
      predicate(branch.condition());
    } else if (node instanceof Node.Fork fork) {
      events(fork.events());
    } else if (node instanceof Node.Guard guard) {
      predicate(guard.pass());
      block(guard.substitute());
    }
  }
}
