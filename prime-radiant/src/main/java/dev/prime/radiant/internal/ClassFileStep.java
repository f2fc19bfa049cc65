package dev.prime.radiant.internal;

import net.bytebuddy.asm.AsmVisitorWrapper;
import net.bytebuddy.description.field.FieldDescription;
import net.bytebuddy.description.field.FieldList;
import net.bytebuddy.description.method.MethodList;
import net.bytebuddy.description.type.TypeDescription;
import net.bytebuddy.implementation.Implementation;
import net.bytebuddy.jar.asm.ClassVisitor;
import net.bytebuddy.pool.TypePool;

/**
 * A step that writes part of a fused class file directly, as ByteBuddy writes the class: it sees
 * only the class visitor, which it wraps. Stateless once built; thread-safe.
 */
abstract class ClassFileStep extends AsmVisitorWrapper.AbstractBase {

  @Override
  public final ClassVisitor wrap(
      TypeDescription instrumentedType,
      ClassVisitor classVisitor,
      Implementation.Context implementationContext,
      TypePool typePool,
      FieldList<FieldDescription.InDefinedShape> declaredFields,
      MethodList<?> methods,
      int writerFlags,
      int readerFlags) {
    return wrap(classVisitor);
  }

  /**
   * {@return a visitor that writes this step's part and passes everything on to {@code next}}
   *
   * @param next the visitor that writes the class
   */
  abstract ClassVisitor wrap(ClassVisitor next);
}
