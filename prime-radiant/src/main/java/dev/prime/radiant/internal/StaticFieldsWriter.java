package dev.prime.radiant.internal;

import net.bytebuddy.jar.asm.ClassVisitor;
import net.bytebuddy.jar.asm.FieldVisitor;
import net.bytebuddy.jar.asm.Opcodes;
import net.bytebuddy.jar.asm.Type;
import net.bytebuddy.utility.OpenedClassReader;

/**
 * Declares a fused class's constant fields ({@code private static final}, see
 * {@link ConstantFields}) directly in the class file as it is written.
 *
 * <p>Design note. ByteBuddy's own {@code defineField} matches every field against every other
 * one, which costs time quadratic in their number; a segment of a long chain has up to
 * {@link FusedCompiler#MAX_SITES} fields, and that matching was most of the time spent compiling
 * a chain of 100,000 distinct blocks. The generated code refers to its fields by name only, so
 * ByteBuddy needs no description of them. Stateless once built; thread-safe.
 */
final class StaticFieldsWriter extends ClassFileStep {
  private final ConstantFields fields;

  StaticFieldsWriter(ConstantFields fields) {
    this.fields = fields;
  }

  @Override
  ClassVisitor wrap(ClassVisitor next) {
    return new ClassVisitor(OpenedClassReader.ASM_API, next) {
      @Override
      public void visitEnd() {
        for (ConstantFields.Field field : fields.all()) {
          FieldVisitor visitor =
              super.visitField(
                  Opcodes.ACC_PRIVATE | Opcodes.ACC_STATIC | Opcodes.ACC_FINAL,
                  field.name(),
                  Type.getDescriptor(field.type()),
                  null,
                  null);
          if (visitor != null) {
            visitor.visitEnd();
          }
        }
        super.visitEnd();
      }
    };
  }
}
