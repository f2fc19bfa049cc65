package dev.prime.radiant.internal;

import net.bytebuddy.jar.asm.ClassVisitor;
import net.bytebuddy.utility.OpenedClassReader;

/**
 * Gives a fused class a source-file attribute that names its chain, so that its frames in a stack
 * trace read {@code Fused_odometry_3.process(fused Radiant chain 'odometry')} rather than {@code
 * (Unknown Source)}. The class has no line numbers: there is no source to point into. Stateless
 * once built; thread-safe.
 */
final class SourceFileWriter extends ClassFileStep {
  private final String source;

  /**
   * @param source what the class's frames show as their file
   */
  SourceFileWriter(String source) {
    this.source = source;
  }

  @Override
  ClassVisitor wrap(ClassVisitor next) {
    return new ClassVisitor(OpenedClassReader.ASM_API, next) {
      @Override
      public void visit(
          int version,
          int access,
          String name,
          String signature,
          String superName,
          String[] interfaces) {
        super.visit(version, access, name, signature, superName, interfaces);
        super.visitSource(source, null);
      }
    };
  }
}
