package dev.prime;

import dev.prime.topology.TopologyNode;

/**
 * How a media compiles the source nodes of the topology model, for a media whose sources live
 * outside the process's memory (Optimus: Redis lists). A media without one
 * ({@code PrimeCore.sourceCompiler()} returns {@code null}, the default) gets the core's in-memory
 * sources, with one service thread per service.
 *
 * <p>Which sources are this media's own is the core's rule, as for chains: a source of this core
 * whose {@link MediaSource#compiledForm()} is an {@code S} ({@link #form()}). A service on such a
 * source is compiled by {@link #service}; a service on any other source (another core's, or an
 * in-memory one) is the core's in-memory service, reading it through its readers. A media never
 * needs to recognise sources by their class.
 *
 * @param <S> the media's form of its own sources
 */
public interface SourceCompiler<S> {

  /** {@return the class of this media's source form} */
  Class<S> form();

  /**
   * Compiles a {@link TopologyNode.EventSource}: this media's source publishing what {@code
   * events} publishes.
   *
   * @param name the node's name
   * @param events its event block (the node's {@link NodeLogic.Events})
   * @param <T> value type
   * @return the source
   */
  <T> Source<T> eventSource(String name, EventBlock<T> events);

  /**
   * Compiles a service of one of this media's sources: a {@link TopologyNode.SourceLink} (runs
   * {@code chain}), a {@link TopologyNode.Filter} ({@link NodeLogic.Condition}), a {@link
   * TopologyNode.FlatMap} ({@link NodeLogic.Expand}) or a {@link TopologyNode.Listener} ({@link
   * NodeLogic.Listen}).
   *
   * <p>If it throws, it must leave nothing behind, as {@link ChainCompiler#toBlock} must: the
   * core then forgets the node and leaves {@code chain} unused, so that the same declaration can
   * be made again once the cause is gone; a {@link ChainAlreadyUsedException} naming the chain
   * says that the media could not undo what it began, and the chain stays consumed.
   *
   * @param node the service's node
   * @param logic its logic
   * @param input the form of the source it reads
   * @param chain for a source link: the chain's form compiled by this media's {@link
   *     ChainCompiler}, consumed; otherwise {@code null}
   * @return the source of its outputs; {@code null} for a listener
   */
  Source<?> service(TopologyNode node, NodeLogic logic, S input, Object chain);
}
