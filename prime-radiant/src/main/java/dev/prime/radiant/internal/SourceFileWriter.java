package dev.prime.radiant.internal;

import net.bytebuddy.asm.AsmVisitorWrapper;
import net.bytebuddy.description.field.FieldDescription;
import net.bytebuddy.description.field.FieldList;
import net.bytebuddy.description.method.MethodList;
import net.bytebuddy.description.type.TypeDescription;
import net.bytebuddy.implementation.Implementation;
import net.bytebuddy.jar.asm.ClassVisitor;
import net.bytebuddy.pool.TypePool;
import net.bytebuddy.utility.OpenedClassReader;

/**
 * Gives a fused class a source-file attribute that names its chain, so that its frames in a stack
 * trace read {@code Fused_odometry_3.process(fused Radiant chain 'odometry')} rather than {@code
 * (Unknown Source)}. The class has no line numbers: there is no source to point into. Stateless
 * once built; thread-safe.
 */
final class SourceFileWriter extends AsmVisitorWrapper.AbstractBase {
  private final String source;

  /**
   * @param source what the class's frames show as their file
   */
  SourceFileWriter(String source) {
    this.source = source;
  }

  @Override
  public ClassVisitor wrap(
      TypeDescription instrumentedType,
      ClassVisitor classVisitor,
      Implementation.Context implementationContext,
      TypePool typePool,
      FieldList<FieldDescription.InDefinedShape> declaredFields,
      MethodList<?> methods,
      int writerFlags,
      int readerFlags) {
    return new ClassVisitor(OpenedClassReader.ASM_API, classVisitor) {
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
