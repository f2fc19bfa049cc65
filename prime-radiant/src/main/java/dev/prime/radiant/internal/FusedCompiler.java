package dev.prime.radiant.internal;

import dev.prime.Block;
import java.lang.reflect.InvocationTargetException;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.atomic.AtomicLong;
import net.bytebuddy.ByteBuddy;
import net.bytebuddy.ClassFileVersion;
import net.bytebuddy.asm.AsmVisitorWrapper;
import net.bytebuddy.description.modifier.TypeManifestation;
import net.bytebuddy.description.modifier.Visibility;
import net.bytebuddy.dynamic.DynamicType;
import net.bytebuddy.implementation.FixedValue;
import net.bytebuddy.implementation.Implementation;
import net.bytebuddy.jar.asm.ClassWriter;
import net.bytebuddy.jar.asm.Opcodes;
import net.bytebuddy.matcher.ElementMatchers;
import net.bytebuddy.pool.TypePool;

/**
 * Compiles a {@link Node} tree into one generated class implementing {@link Block}.
 *
 * <p>Design note. The class is written with ByteBuddy ({@link ProcessEmitter} writes the method
 * body through ByteBuddy's ASM), defined in a {@link FusedClassLoader} of its own (so it is
 * unloaded with its block) and handed its constants through {@link FusedConstants}. One tree gives
 * one class, except for very large trees: HotSpot neither compiles methods over 8000 bytes of
 * bytecode nor inlines into them much, so a tree with more than {@link #MAX_SITES} call sites is
 * cut: its heaviest subtrees are compiled first, each into a class of its own, and called from the
 * outer class as one opaque block. Thread-safe and stateless apart from a counter for class names.
 */
public final class FusedCompiler {
  /** Most call sites in one generated method (each 12 to 20 bytes of bytecode). */
  public static final int MAX_SITES = 200;

  private static final String PACKAGE = "dev.prime.radiant.fused.";
  private static final AtomicLong CLASSES = new AtomicLong();
  /** Descriptions of Prime's and the JDK's types, for frame computation; cached, thread-safe. */
  private static final TypePool TYPES = TypePool.Default.of(FusedCompiler.class.getClassLoader());

  private FusedCompiler() {}

  /** How many classes this JVM generated so far (all Radiant cores together). */
  public static long classesGenerated() {
    return CLASSES.get();
  }

  /**
   * Compiles a chain.
   *
   * @param chainName the chain's name (for the class name, its loader and {@code toString})
   * @param root the chain's tree
   * @param <I> input type
   * @param <O> output type
   * @return a new instance of the generated class
   */
  public static <I, O> Block<I, O> compile(String chainName, Node root) {
    return define(chainName, fit(chainName, root));
  }

  /** Cuts subtrees off until no method has more than {@link #MAX_SITES} call sites. */
  private static Node fit(String chainName, Node node) {
    List<Node> children = node.children();
    if (!children.isEmpty()) {
      List<Node> fitted = new ArrayList<>(children.size());
      for (Node child : children) {
        fitted.add(fit(chainName, child));
      }
      node = node.withChildren(fitted);
    }
    while (node.sites() > MAX_SITES) {
      List<Node> parts = new ArrayList<>(node.children());
      int heaviest = 0;
      for (int i = 1; i < parts.size(); i++) {
        if (parts.get(i).sites() > parts.get(heaviest).sites()) {
          heaviest = i;
        }
      }
      if (parts.get(heaviest).sites() <= 1) {
        break; // nothing left to cut: the node itself is small
      }
      parts.set(heaviest, new Node.Opaque(define(chainName, parts.get(heaviest))));
      node = node.withChildren(parts);
    }
    return node;
  }

  private static <I, O> Block<I, O> define(String chainName, Node root) {
    ClassLoader prime = FusedCompiler.class.getClassLoader();
    ConstantFields fields = ConstantFields.of(root, prime);
    String binaryName = PACKAGE + "Fused_" + identifier(chainName) + "_" + CLASSES.incrementAndGet();
    String owner = binaryName.replace('.', '/');
    ProcessEmitter emitter = new ProcessEmitter(root, fields, owner);

    DynamicType.Builder<Object> builder =
        new ByteBuddy(ClassFileVersion.JAVA_V17)
            .subclass(Object.class)
            .name(binaryName)
            .modifiers(Visibility.PUBLIC, TypeManifestation.FINAL)
            .implement(Block.class);
    Object[] values = new Object[fields.all().size()];
    for (int i = 0; i < values.length; i++) {
      ConstantFields.Field field = fields.all().get(i);
      builder =
          builder.defineField(
              field.name(),
              field.type(),
              Opcodes.ACC_PRIVATE | Opcodes.ACC_STATIC | Opcodes.ACC_FINAL);
      values[i] = field.value();
    }
    byte[] bytes =
        builder
            .initializer(emitter.initializer())
            .defineMethod("process", Object.class, Visibility.PUBLIC)
            .withParameters(Object.class)
            .intercept(new Implementation.Simple(emitter))
            .method(ElementMatchers.named("toString"))
            .intercept(FixedValue.value("fused Radiant chain '" + chainName + "'"))
            .visit(new AsmVisitorWrapper.ForDeclaredMethods().writerFlags(ClassWriter.COMPUTE_FRAMES))
            .make(TYPES)
            .getBytes();

    Class<?> type = new FusedClassLoader(chainName, prime).define(binaryName, bytes);
    FusedConstants.initialize(type, values);
    try {
      @SuppressWarnings("unchecked")
      Block<I, O> block = (Block<I, O>) type.getConstructor().newInstance();
      return block;
    } catch (InstantiationException
        | IllegalAccessException
        | InvocationTargetException
        | NoSuchMethodException e) {
      throw new IllegalStateException("cannot instantiate the fused class of " + chainName, e);
    }
  }

  /** A Java identifier made of a chain name, for readable stack traces. */
  private static String identifier(String chainName) {
    StringBuilder b = new StringBuilder();
    for (int i = 0; i < chainName.length() && b.length() < 40; i++) {
      char c = chainName.charAt(i);
      boolean plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
      if (plain) {
        b.append(c);
      } else if (b.length() > 0 && b.charAt(b.length() - 1) != '_') {
        b.append('_');
      }
    }
    return b.length() == 0 ? "chain" : b.toString();
  }
}
