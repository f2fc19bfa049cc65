package dev.prime.conformance;

import dev.prime.Block;
import java.io.IOException;
import java.lang.reflect.InvocationHandler;
import java.lang.reflect.Method;
import java.lang.reflect.Proxy;
import java.util.List;
import java.util.function.Predicate;

/**
 * Blocks of every kind of class a user may write, for {@link BlockKindsConformance}: each adds its
 * own power of two to its input, so a result tells which blocks ran, and each fails on {@link
 * #FAIL} with an exception it makes in its own {@code process} (a checked {@link IOException},
 * thrown sneakily; the proxy's handler an unchecked one, which a proxy passes on unchanged).
 */
final class BlockKinds {
  /** The input every kind fails on. */
  static final int FAIL = -1_000;

  private BlockKinds() {}

  /** A kind of block: its name, the block, what it adds and the class its failure is made in. */
  record Kind(String name, Block<Integer, Integer> block, int adds, String failsIn) {}

  /** One block of every kind, a new object each (the stateful ones must not be shared). */
  static List<Kind> all() {
    return List.of(
        new Kind("public-class", new Exported(), 1, Exported.class.getName()),
        new Kind("package-private-class", new PackagePrivate(), 2, PackagePrivate.class.getName()),
        new Kind("private-class", new Private(), 4, Private.class.getName()),
        new Kind("inherited-process", new InheritsProcess(), 8, Base.class.getName()),
        new Kind("default-method", new UsesDefault(), 16, WithDefault.class.getName()),
        new Kind("generic-class", new Generic<Integer>(), 32, Generic.class.getName()),
        new Kind("enum-constant", Singleton.INSTANCE, 64, Singleton.class.getName()),
        new Kind("anonymous-class", anonymous(), 128, anonymous().getClass().getName()),
        new Kind("lambda", lambda(256), 256, BlockKinds.class.getName()),
        new Kind("method-reference", BlockKinds::plus512, 512, BlockKinds.class.getName()),
        new Kind("proxy", proxy(), 1024, Handler.class.getName()));
  }

  /** The sum of what every kind adds. */
  static int sum() {
    return all().stream().mapToInt(Kind::adds).sum();
  }

  /** Throws any throwable, checked or not, without declaring it. */
  @SuppressWarnings("unchecked")
  static <E extends Throwable> RuntimeException sneaky(Throwable t) throws E {
    throw (E) t;
  }

  /** Public, in the kit's package: a media may call it by its own class. */
  public static final class Exported implements Block<Integer, Integer> {
    @Override
    public Integer process(Integer x) {
      if (x == FAIL) {
        throw sneaky(new IOException("public-class failed on " + x));
      }
      return x + 1;
    }
  }

  /** Package-private. */
  static final class PackagePrivate implements Block<Integer, Integer> {
    @Override
    public Integer process(Integer x) {
      if (x == FAIL) {
        throw sneaky(new IOException("package-private-class failed on " + x));
      }
      return x + 2;
    }
  }

  /** Private. */
  private static final class Private implements Block<Integer, Integer> {
    @Override
    public Integer process(Integer x) {
      if (x == FAIL) {
        throw sneaky(new IOException("private-class failed on " + x));
      }
      return x + 4;
    }
  }

  /** Package-private, declaring the process its public subclass inherits. */
  abstract static class Base implements Block<Integer, Integer> {
    @Override
    public Integer process(Integer x) {
      if (x == FAIL) {
        throw sneaky(new IOException("inherited-process failed on " + x));
      }
      return x + 8;
    }
  }

  /** Public, its process inherited from a class no other package can name. */
  public static final class InheritsProcess extends Base {}

  /** A block interface with process as a default method. */
  public interface WithDefault extends Block<Integer, Integer> {
    @Override
    default Integer process(Integer x) {
      if (x == FAIL) {
        throw sneaky(new IOException("default-method failed on " + x));
      }
      return x + 16;
    }
  }

  /** Public, its process a default method of an interface. */
  public static final class UsesDefault implements WithDefault {}

  /** Generic, its input erased to its bound: process(Integer) and a bridge process(Object). */
  public static final class Generic<T extends Integer> implements Block<T, Integer> {
    @Override
    public Integer process(T x) {
      if (x == FAIL) {
        throw sneaky(new IOException("generic-class failed on " + x));
      }
      return x + 32;
    }
  }

  /** An enum constant. */
  public enum Singleton implements Block<Integer, Integer> {
    /** The one block. */
    INSTANCE;

    @Override
    public Integer process(Integer x) {
      if (x == FAIL) {
        throw sneaky(new IOException("enum-constant failed on " + x));
      }
      return x + 64;
    }
  }

  private static Block<Integer, Integer> anonymous() {
    return new Block<>() {
      @Override
      public Integer process(Integer x) {
        if (x == FAIL) {
          throw sneaky(new IOException("anonymous-class failed on " + x));
        }
        return x + 128;
      }
    };
  }

  /** A lambda that captures what it adds, so each is an object of its own. */
  private static Block<Integer, Integer> lambda(int adds) {
    return x -> {
      if (x == FAIL) {
        throw sneaky(new IOException("lambda failed on " + x));
      }
      return x + adds;
    };
  }

  private static Integer plus512(Integer x) {
    if (x == FAIL) {
      throw sneaky(new IOException("method-reference failed on " + x));
    }
    return x + 512;
  }

  @SuppressWarnings("unchecked")
  private static Block<Integer, Integer> proxy() {
    return (Block<Integer, Integer>)
        Proxy.newProxyInstance(
            BlockKinds.class.getClassLoader(), new Class<?>[] {Block.class}, new Handler());
  }

  /** The proxy's handler: process adds 1024; a checked exception would reach the caller wrapped. */
  private static final class Handler implements InvocationHandler {
    @Override
    public Object invoke(Object proxy, Method method, Object[] args) {
      return switch (method.getName()) {
        case "process" -> {
          int x = (Integer) args[0];
          if (x == FAIL) {
            throw new IllegalStateException("proxy failed on " + x);
          }
          yield x + 1024;
        }
        case "hashCode" -> System.identityHashCode(proxy);
        case "equals" -> proxy == args[0];
        default -> "proxy block";
      };
    }
  }

  /** A public predicate class: holds for even numbers. */
  public static final class IsEven implements Predicate<Integer> {
    @Override
    public boolean test(Integer x) {
      return x % 2 == 0;
    }
  }

  /** A private predicate class: holds for positive numbers. */
  private static final class IsPositive implements Predicate<Integer> {
    @Override
    public boolean test(Integer x) {
      return x > 0;
    }
  }

  /** {@link IsPositive}, which no other class can name. */
  static Predicate<Integer> isPositive() {
    return new IsPositive();
  }
}
