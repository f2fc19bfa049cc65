package dev.prime.radiant.internal;

import dev.prime.Block;
import java.lang.reflect.InvocationTargetException;
import java.util.concurrent.atomic.AtomicLong;
import java.util.function.Consumer;
import net.bytebuddy.ByteBuddy;
import net.bytebuddy.ClassFileVersion;
import net.bytebuddy.asm.AsmVisitorWrapper;
import net.bytebuddy.description.modifier.TypeManifestation;
import net.bytebuddy.description.modifier.Visibility;
import net.bytebuddy.implementation.FixedValue;
import net.bytebuddy.implementation.Implementation;
import net.bytebuddy.jar.asm.ClassWriter;
import net.bytebuddy.matcher.ElementMatchers;
import net.bytebuddy.pool.TypePool;

/**
 * Compiles a {@link Node} tree into generated classes implementing {@link Block}.
 *
 * <p>Design note. A class is written with ByteBuddy ({@link ProcessEmitter} writes the method body
 * through ByteBuddy's ASM), defined in the {@link FusedClassLoader} of its chain (so it is
 * unloaded with the chain's block) and handed its constants through {@link FusedConstants}. A
 * chain of up to {@link #MAX_SITES} call sites, templates included, is one class with one
 * straight-line {@code process} method, small enough for the JIT to compile and to inline every
 * block into. Longer chains are split by {@link TreeSplitter}: HotSpot never compiles a method
 * over 8000 bytes of bytecode ({@code HugeMethodLimit}), a method has at most 64 KB of code, and a
 * class's constant pool at most 65535 entries, so a chain of n blocks becomes about
 * n / {@code MAX_SITES} segment classes run one after the other by a small driver class (drivers
 * of drivers past {@code MAX_SITES} segments). Every class keeps its own call sites, so profiles
 * stay monomorphic in every segment. Nothing here recurses over the tree: chains of 100,000
 * links compile on a default thread stack. Thread-safe and stateless apart from a counter for
 * class names.
 */
public final class FusedCompiler {
  /**
   * Most call sites in one generated method (each 7 to 20 bytes of bytecode, plus 6 bytes per
   * distinct chain name in the failure handlers: at most about 5 KB, under HotSpot's 8000-byte
   * limit for compiling a method at all).
   */
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
   * @param chainName the chain's name (for the class names, their loader and {@code toString})
   * @param root the chain's tree
   * @param <I> input type
   * @param <O> output type
   * @return a new instance of the generated class that runs the whole chain
   */
  public static <I, O> Block<I, O> compile(String chainName, Node root) {
    return compile(chainName, root, bytes -> {});
  }

  /**
   * Compiles a chain and shows every class file written (for tests of the class-file limits).
   *
   * @param chainName the chain's name
   * @param root the chain's tree
   * @param classFiles receives each class file, segments first, the chain's own class last
   * @return a new instance of the generated class that runs the whole chain
   */
  static <I, O> Block<I, O> compile(String chainName, Node root, Consumer<byte[]> classFiles) {
    FusedClassLoader loader =
        new FusedClassLoader(chainName, FusedCompiler.class.getClassLoader());
    TreeSplitter splitter =
        new TreeSplitter(
            MAX_SITES,
            piece ->
                define(loader, chainName, "part of fused Radiant chain '", piece, classFiles));
    return define(
        loader, chainName, "fused Radiant chain '", splitter.split(root), classFiles);
  }

  private static <I, O> Block<I, O> define(
      FusedClassLoader loader,
      String chainName,
      String description,
      Node root,
      Consumer<byte[]> classFiles) {
    ConstantFields fields = ConstantFields.of(root, loader);
    String binaryName = PACKAGE + "Fused_" + identifier(chainName) + "_" + CLASSES.incrementAndGet();
    String owner = binaryName.replace('.', '/');
    ProcessEmitter emitter = new ProcessEmitter(root, fields, owner);

    Object[] values = new Object[fields.all().size()];
    for (int i = 0; i < values.length; i++) {
      values[i] = fields.all().get(i).value();
    }
    byte[] bytes =
        new ByteBuddy(ClassFileVersion.JAVA_V17)
            .subclass(Object.class)
            .name(binaryName)
            .modifiers(Visibility.PUBLIC, TypeManifestation.FINAL)
            .implement(Block.class)
            .initializer(emitter.initializer())
            .defineMethod("process", Object.class, Visibility.PUBLIC)
            .withParameters(Object.class)
            .intercept(new Implementation.Simple(emitter))
            .method(ElementMatchers.named("toString"))
            .intercept(FixedValue.value(description + chainName + "'"))
            .visit(new AsmVisitorWrapper.ForDeclaredMethods().writerFlags(ClassWriter.COMPUTE_FRAMES))
            .visit(new StaticFieldsWriter(fields))
            .visit(new SourceFileWriter(description + chainName + "'"))
            .make(TYPES)
            .getBytes();

    classFiles.accept(bytes);
    Class<?> type = loader.define(binaryName, bytes);
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
