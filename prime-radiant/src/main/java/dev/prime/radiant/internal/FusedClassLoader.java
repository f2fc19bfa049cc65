package dev.prime.radiant.internal;

/**
 * The class loader of one fused chain: its class, and for a long chain its segment classes.
 *
 * <p>Design note. Each fused chain gets a loader of its own, so its classes (and the loader) can
 * be unloaded as soon as the chain's block is no longer referenced. The classes of one chain
 * refer to each other by name (a driver calls its segments by their own type), which this loader
 * resolves because it defined them. Hidden classes
 * ({@code Lookup.defineHiddenClass}) would be unloadable too, but the JVM leaves their frames out
 * of stack traces and of {@code StackWalker} by default, and Radiant promises that a failing
 * user block shows up directly under the fused chain that called it. The parent is the loader of
 * Prime's own classes, which the generated code refers to; user blocks are referred to by their
 * class only when that loader resolves the same class.
 */
final class FusedClassLoader extends ClassLoader {

  FusedClassLoader(String chainName, ClassLoader parent) {
    super("prime-radiant[" + chainName + "]", parent);
    // On the module path Radiant is a named module exporting only dev.prime.radiant; the fused
    // classes live in this loader's unnamed module and read FusedConstants from this package.
    // On the class path Radiant is unnamed itself and this does nothing.
    FusedClassLoader.class
        .getModule()
        .addExports(FusedClassLoader.class.getPackageName(), getUnnamedModule());
  }

  Class<?> define(String binaryName, byte[] bytes) {
    return defineClass(binaryName, bytes, 0, bytes.length);
  }
}
