package dev.prime;


/**
 * A media's source that can open readers for the core's own services (a chain linked to it, a
 * collector, a filter) apart from the readers a program opens with {@link #reader()}: only the
 * program's readers are listed in the {@linkplain dev.prime.topology.Topology topology}, so the
 * diagram is the same whether a media reads a source through readers or in its own way.
 *
 * @param <T> value type
 */
public interface MediaSource<T> extends Source<T> {

  /**
   * A reader for a service of the diagram, positioned like {@link #reader()}, not recorded in the
   * topology.
   *
   * @return a new reader
   */
  Reader<T> serviceReader();

  /**
   * What this media compiled the source to, that a service of the same core reads it through
   * (Optimus: its Redis keys); {@code null} (the default) for a source the core's in-memory
   * services read through readers. See {@link SourceCompiler}.
   *
   * @return the compiled form, or {@code null}
   */
  default Object compiledForm() {
    return null;
  }
}
