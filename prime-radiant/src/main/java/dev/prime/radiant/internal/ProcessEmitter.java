package dev.prime.radiant.internal;

import static net.bytebuddy.jar.asm.Opcodes.AALOAD;
import static net.bytebuddy.jar.asm.Opcodes.ALOAD;
import static net.bytebuddy.jar.asm.Opcodes.ARETURN;
import static net.bytebuddy.jar.asm.Opcodes.ASTORE;
import static net.bytebuddy.jar.asm.Opcodes.ATHROW;
import static net.bytebuddy.jar.asm.Opcodes.CHECKCAST;
import static net.bytebuddy.jar.asm.Opcodes.DUP;
import static net.bytebuddy.jar.asm.Opcodes.GETSTATIC;
import static net.bytebuddy.jar.asm.Opcodes.GOTO;
import static net.bytebuddy.jar.asm.Opcodes.IFEQ;
import static net.bytebuddy.jar.asm.Opcodes.IFNE;
import static net.bytebuddy.jar.asm.Opcodes.IFNULL;
import static net.bytebuddy.jar.asm.Opcodes.INSTANCEOF;
import static net.bytebuddy.jar.asm.Opcodes.INVOKEINTERFACE;
import static net.bytebuddy.jar.asm.Opcodes.INVOKESPECIAL;
import static net.bytebuddy.jar.asm.Opcodes.INVOKESTATIC;
import static net.bytebuddy.jar.asm.Opcodes.INVOKEVIRTUAL;
import static net.bytebuddy.jar.asm.Opcodes.NEW;
import static net.bytebuddy.jar.asm.Opcodes.POP;
import static net.bytebuddy.jar.asm.Opcodes.PUTSTATIC;
import static net.bytebuddy.jar.asm.Opcodes.SWAP;

import dev.prime.Block;
import dev.prime.ChainFailedException;
import dev.prime.CoreClosedException;
import dev.prime.EventBlock;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Deque;
import java.util.Iterator;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.function.Predicate;
import net.bytebuddy.description.method.MethodDescription;
import net.bytebuddy.implementation.Implementation;
import net.bytebuddy.implementation.bytecode.ByteCodeAppender;
import net.bytebuddy.jar.asm.Label;
import net.bytebuddy.jar.asm.MethodVisitor;
import net.bytebuddy.jar.asm.Type;

/**
 * Writes the bytecode of a fused class: {@code process(Object)} for the whole tree, and the
 * static initializer that fills the constant fields.
 *
 * <p>Design note. {@code process} is one straight-line method. Each leaf is an
 * {@code invokevirtual} on the leaf's own class (or {@code invokeinterface Block.process} when
 * that class cannot be named) with a {@code static final} receiver, so every leaf has a call site
 * of its own and the JIT sees a constant receiver. Links are local variables, if/else and guards
 * are branches, for-each is a loop, a union builds its tuple in place. Between the blocks of a
 * link the value stays on the operand stack (a leaf then costs {@code getstatic; swap; invoke}),
 * which keeps the method small enough for the JIT to inline it into its caller up to about 20
 * blocks. Failure naming is in the
 * exception table: every call the chain makes is covered by a {@code Throwable} range whose
 * handler pushes the name of the chain that owns the call and jumps to one shared handler, which
 * rethrows {@link ChainFailedException}, {@link CoreClosedException} and
 * {@link VirtualMachineError} unchanged and wraps
 * anything else in a {@code ChainFailedException} naming that chain. Nothing runs on the normal
 * path but the calls. Each local variable slot holds one type only, so frames are simple to
 * compute. Stateless and thread-safe: the generated method keeps its state in locals.
 *
 * <p>A {@link Node.Sequence} (links flattened) is its steps one after the other, the value on the
 * stack between them. The tree is expanded from a stack of pending steps, not by recursion, so
 * the depth of a tree never becomes the depth of the compiler's stack.
 */
final class ProcessEmitter implements ByteCodeAppender {
  private static final String OBJECT_TO_OBJECT = "(Ljava/lang/Object;)Ljava/lang/Object;";
  private static final String OBJECT_TO_BOOLEAN = "(Ljava/lang/Object;)Z";
  private static final String THROWABLE = Type.getInternalName(Throwable.class);
  private static final String VM_ERROR = Type.getInternalName(VirtualMachineError.class);
  private static final String CHAIN_FAILED = Type.getInternalName(ChainFailedException.class);
  private static final String CORE_CLOSED = Type.getInternalName(CoreClosedException.class);
  private static final String LIST = Type.getInternalName(List.class);
  private static final String ARRAY_LIST = Type.getInternalName(ArrayList.class);
  private static final String ITERATOR = Type.getInternalName(Iterator.class);
  /** Deep enough for a 5-tuple under construction plus a call. */
  private static final int MAX_STACK = 8;
  /** Instead of a local variable: the input is on top of the operand stack. */
  private static final int ON_STACK = -1;

  private final Node root;
  private final ConstantFields fields;
  private final String owner;

  ProcessEmitter(Node root, ConstantFields fields, String owner) {
    this.root = root;
    this.fields = fields;
    this.owner = owner;
  }

  @Override
  public Size apply(MethodVisitor mv, Implementation.Context context, MethodDescription method) {
    Writer writer = new Writer(mv);
    writer.emitAll(root, 1);
    mv.visitInsn(ARETURN);
    writer.emitHandlers();
    return new Size(MAX_STACK, writer.nextLocal);
  }

  /** The static initializer's part: {@code field_i = (T_i) FusedConstants.take()[i]}. */
  ByteCodeAppender initializer() {
    return (mv, context, method) -> {
      mv.visitMethodInsn(
          INVOKESTATIC,
          Type.getInternalName(FusedConstants.class),
          "take",
          "()[Ljava/lang/Object;",
          false);
      mv.visitVarInsn(ASTORE, 0);
      List<ConstantFields.Field> all = fields.all();
      for (int i = 0; i < all.size(); i++) {
        ConstantFields.Field field = all.get(i);
        mv.visitVarInsn(ALOAD, 0);
        mv.visitLdcInsn(i);
        mv.visitInsn(AALOAD);
        mv.visitTypeInsn(CHECKCAST, Type.getInternalName(field.type()));
        mv.visitFieldInsn(PUTSTATIC, owner, field.name(), Type.getDescriptor(field.type()));
      }
      return new Size(3, 1);
    };
  }

  /** Writes one method; not reused. */
  private final class Writer {
    private final MethodVisitor mv;
    private final Map<String, Label> handlers = new LinkedHashMap<>();
    /** Code still to write, next first: the tree is expanded from here, never recursively. */
    private final Deque<Runnable> pending = new ArrayDeque<>();
    private int nextLocal = 2; // 0: this, 1: the input

    Writer(MethodVisitor mv) {
      this.mv = mv;
    }

    /**
     * Emits {@code root} applied to the value in local {@code input}; leaves the output on the
     * stack. Nodes are expanded from a stack of pending steps, not by recursion.
     */
    void emitAll(Node root, int input) {
      emit(root, input);
      while (!pending.isEmpty()) {
        pending.pop().run();
      }
    }

    /** Schedules {@code steps} to run next, in this order, before anything scheduled earlier. */
    private void next(Runnable... steps) {
      for (int i = steps.length - 1; i >= 0; i--) {
        pending.push(steps[i]);
      }
    }

    /**
     * Emits {@code node} applied to the value in local {@code input} (or on the stack, if
     * {@link #ON_STACK}); leaves the output on the stack. Code of the node itself is written now,
     * its children's code is scheduled with {@link #next}.
     */
    private void emit(Node node, int input) {
      boolean takesStack =
          node instanceof Node.Leaf
              || node instanceof Node.Opaque
              || node instanceof Node.Link
              || node instanceof Node.Sequence;
      if (input == ON_STACK && !takesStack) {
        input = store();
      }
      emitFrom(node, input);
    }

    private void emitFrom(Node node, int input) {
      if (node instanceof Node.Leaf leaf) {
        named(leaf.chain(), () -> callBlock(fields.block(leaf.block()), input));
      } else if (node instanceof Node.Opaque opaque) {
        callBlock(fields.block(opaque.block()), input);
      } else if (node instanceof Node.Link link) {
        next(() -> emit(link.first(), input), () -> emit(link.second(), ON_STACK));
      } else if (node instanceof Node.Sequence sequence) {
        List<Node> steps = sequence.steps();
        Runnable[] all = new Runnable[steps.size()];
        for (int i = 0; i < all.length; i++) {
          Node step = steps.get(i);
          int from = i == 0 ? input : ON_STACK;
          all[i] = () -> emit(step, from);
        }
        next(all);
      } else if (node instanceof Node.IfElse branch) {
        emitBranch(
            branch.chain(),
            branch.condition(),
            input,
            () -> emit(branch.then(), input),
            () -> emit(branch.otherwise(), input));
      } else if (node instanceof Node.Guard guard) {
        emitBranch(
            guard.chain(),
            guard.pass(),
            input,
            () -> emit(guard.body(), input),
            () -> named(guard.chain(), () -> callBlock(fields.block(guard.substitute()), input)));
      } else if (node instanceof Node.ForEach loop) {
        emitForEach(loop, input);
      } else if (node instanceof Node.Union union) {
        emitUnion(union, input);
      } else if (node instanceof Node.Fork fork) {
        emitFork(fork, input);
      } else {
        throw new IllegalStateException("unknown node " + node);
      }
    }

    private void emitBranch(
        String chain, Predicate<?> condition, int input, Runnable then, Runnable otherwise) {
      Label elseLabel = new Label();
      Label end = new Label();
      named(chain, () -> callPredicate(fields.predicate(condition), input));
      mv.visitJumpInsn(IFEQ, elseLabel);
      next(
          then,
          () -> {
            mv.visitJumpInsn(GOTO, end);
            mv.visitLabel(elseLabel);
          },
          otherwise,
          () -> mv.visitLabel(end));
    }

    private void emitForEach(Node.ForEach loop, int input) {
      int list = nextLocal++;
      int out = nextLocal++;
      int iterator = nextLocal++;
      named(
          loop.chain(),
          () -> {
            mv.visitVarInsn(ALOAD, input);
            mv.visitLdcInsn("for-each input list must not be null");
            mv.visitMethodInsn(
                INVOKESTATIC,
                Type.getInternalName(Objects.class),
                "requireNonNull",
                "(Ljava/lang/Object;Ljava/lang/String;)Ljava/lang/Object;",
                false);
            mv.visitTypeInsn(CHECKCAST, LIST);
            mv.visitVarInsn(ASTORE, list);
            mv.visitTypeInsn(NEW, ARRAY_LIST);
            mv.visitInsn(DUP);
            mv.visitVarInsn(ALOAD, list);
            mv.visitMethodInsn(INVOKEINTERFACE, LIST, "size", "()I", true);
            mv.visitMethodInsn(INVOKESPECIAL, ARRAY_LIST, "<init>", "(I)V", false);
            mv.visitVarInsn(ASTORE, out);
            mv.visitVarInsn(ALOAD, list);
            mv.visitMethodInsn(INVOKEINTERFACE, LIST, "iterator", "()Ljava/util/Iterator;", true);
            mv.visitVarInsn(ASTORE, iterator);
          });
      Label head = new Label();
      Label done = new Label();
      mv.visitLabel(head);
      named(
          loop.chain(),
          () -> {
            mv.visitVarInsn(ALOAD, iterator);
            mv.visitMethodInsn(INVOKEINTERFACE, ITERATOR, "hasNext", "()Z", true);
          });
      mv.visitJumpInsn(IFEQ, done);
      int element = nextLocal++;
      named(
          loop.chain(),
          () -> {
            mv.visitVarInsn(ALOAD, iterator);
            mv.visitMethodInsn(
                INVOKEINTERFACE, ITERATOR, "next", "()Ljava/lang/Object;", true);
            mv.visitVarInsn(ASTORE, element);
          });
      next(
          () -> emit(loop.body(), element),
          () -> {
            int value = store();
            named(
                loop.chain(),
                () -> {
                  mv.visitVarInsn(ALOAD, out);
                  mv.visitVarInsn(ALOAD, value);
                  mv.visitMethodInsn(
                      INVOKEVIRTUAL, ARRAY_LIST, "add", "(Ljava/lang/Object;)Z", false);
                  mv.visitInsn(POP);
                });
            mv.visitJumpInsn(GOTO, head);
            mv.visitLabel(done);
            mv.visitVarInsn(ALOAD, out);
          });
    }

    private void emitUnion(Node.Union union, int input) {
      List<Node> parts = union.parts();
      int[] outputs = new int[parts.size()];
      Runnable[] steps = new Runnable[2 * outputs.length + 1];
      for (int i = 0; i < outputs.length; i++) {
        Node part = parts.get(i);
        int index = i;
        steps[2 * i] = () -> emit(part, input);
        steps[2 * i + 1] = () -> outputs[index] = store();
      }
      String tuple = "dev/prime/Tuple" + outputs.length;
      steps[steps.length - 1] =
          () ->
              named(
                  union.chain(),
                  () -> {
                    mv.visitTypeInsn(NEW, tuple);
                    mv.visitInsn(DUP);
                    for (int slot : outputs) {
                      mv.visitVarInsn(ALOAD, slot);
                    }
                    mv.visitMethodInsn(
                        INVOKESPECIAL,
                        tuple,
                        "<init>",
                        "(" + "Ljava/lang/Object;".repeat(outputs.length) + ")V",
                        false);
                  });
      next(steps);
    }

    private void emitFork(Node.Fork fork, int input) {
      next(
          () -> emit(fork.body(), input),
          () -> {
            int output = store();
            Label skip = new Label();
            mv.visitVarInsn(ALOAD, output);
            mv.visitJumpInsn(IFNULL, skip);
            ConstantFields.Field events = fields.events(fork.events());
            named(
                fork.chain(),
                () -> {
                  mv.visitFieldInsn(
                      GETSTATIC, owner, events.name(), Type.getDescriptor(events.type()));
                  mv.visitVarInsn(ALOAD, output);
                  mv.visitMethodInsn(
                      INVOKEVIRTUAL,
                      Type.getInternalName(EventBlock.class),
                      "publish",
                      "(Ljava/lang/Object;)V",
                      false);
                });
            mv.visitLabel(skip);
            mv.visitVarInsn(ALOAD, output);
          });
    }

    private void callBlock(ConstantFields.Field field, int input) {
      call(field, input, Block.class, "process", OBJECT_TO_OBJECT);
    }

    private void callPredicate(ConstantFields.Field field, int input) {
      call(field, input, Predicate.class, "test", OBJECT_TO_BOOLEAN);
    }

    private void call(
        ConstantFields.Field field, int input, Class<?> api, String method, String descriptor) {
      mv.visitFieldInsn(GETSTATIC, owner, field.name(), Type.getDescriptor(field.type()));
      if (input == ON_STACK) {
        mv.visitInsn(SWAP);
      } else {
        mv.visitVarInsn(ALOAD, input);
      }
      if (field.viaInterface()) {
        mv.visitMethodInsn(INVOKEINTERFACE, Type.getInternalName(api), method, descriptor, true);
      } else {
        mv.visitMethodInsn(
            INVOKEVIRTUAL, Type.getInternalName(field.type()), method, descriptor, false);
      }
    }

    /** Stores the top of the stack in a fresh local (typed Object by use). */
    private int store() {
      int slot = nextLocal++;
      mv.visitVarInsn(ASTORE, slot);
      return slot;
    }

    /** Emits {@code code} inside a range whose failures are reported as {@code chain}'s. */
    private void named(String chain, Runnable code) {
      Label start = new Label();
      Label end = new Label();
      Label handler = handlers.computeIfAbsent(chain, c -> new Label());
      mv.visitTryCatchBlock(start, end, handler, THROWABLE);
      mv.visitLabel(start);
      code.run();
      mv.visitLabel(end);
    }

    /** One entry per chain name (push the name), then the shared wrap-or-rethrow code. */
    void emitHandlers() {
      if (handlers.isEmpty()) {
        return;
      }
      Label common = new Label();
      for (Map.Entry<String, Label> entry : handlers.entrySet()) {
        mv.visitLabel(entry.getValue());
        mv.visitLdcInsn(entry.getKey());
        mv.visitJumpInsn(GOTO, common);
      }
      int name = nextLocal++;
      int failure = nextLocal++;
      Label rethrow = new Label();
      mv.visitLabel(common);
      mv.visitVarInsn(ASTORE, name);
      mv.visitVarInsn(ASTORE, failure);
      mv.visitVarInsn(ALOAD, failure);
      mv.visitTypeInsn(INSTANCEOF, CHAIN_FAILED);
      mv.visitJumpInsn(IFNE, rethrow);
      mv.visitVarInsn(ALOAD, failure);
      mv.visitTypeInsn(INSTANCEOF, CORE_CLOSED);
      mv.visitJumpInsn(IFNE, rethrow);
      mv.visitVarInsn(ALOAD, failure);
      mv.visitTypeInsn(INSTANCEOF, VM_ERROR);
      mv.visitJumpInsn(IFNE, rethrow);
      mv.visitTypeInsn(NEW, CHAIN_FAILED);
      mv.visitInsn(DUP);
      mv.visitVarInsn(ALOAD, name);
      mv.visitVarInsn(ALOAD, failure);
      mv.visitMethodInsn(
          INVOKESPECIAL,
          CHAIN_FAILED,
          "<init>",
          "(Ljava/lang/String;Ljava/lang/Throwable;)V",
          false);
      mv.visitInsn(ATHROW);
      mv.visitLabel(rethrow);
      mv.visitVarInsn(ALOAD, failure);
      mv.visitInsn(ATHROW);
    }
  }
}
