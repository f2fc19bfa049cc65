package dev.prime;

import java.util.Objects;

/**
 * The metrics of one metered node of a core's diagram at one moment (see {@link Metrics} for
 * which nodes are metered and what each number means per kind). Immutable.
 *
 * <p>The numbers count since the core was created, in this process: on Optimus, what the services
 * this process hosts did (and the sources it published to). They are read one after another while
 * the services run, so a value in flight may show in {@code valuesIn} and not yet in {@code
 * valuesOut} or {@code processing}; once the diagram is idle they agree.
 *
 * @param name the node's name in the topology model ({@link PrimeCore#topology()}), the same on
 *     every media
 * @param pseudoname the readable name given at creation, or {@code null}
 * @param kind the kind of node: the simple name of its {@link dev.prime.topology.TopologyNode}
 *     record ({@code BlockChain}, {@code IfElse}, {@code Filter}, {@code EventSource}, ...)
 * @param valuesIn values given to the node: calls of a chain, values a filter, flat-map or
 *     listener took from its input, publishes to a source, calls of a generic service's {@code
 *     work}, values a combinator took from its inputs, ticks a timer published
 * @param valuesOut values it gave out: a chain's non-null outputs, values a filter passed, values
 *     a flat-map made (non-null), publishes a source's media accepted, a generic service's {@code
 *     work} calls that returned, values a combinator published, ticks; always 0 for a listener
 * @param failures values on which the node's logic threw
 * @param deadLetters values the media set aside as dead letters (Optimus: the service's dead-letter
 *     list in Redis, counted for every process since the topology's Redis data was created,
 *     trimmed ones included; {@code -1} while it cannot be read now: Redis unreachable, or the
 *     core closed); always 0 on media without dead letters (Liberty, Radiant)
 * @param queueDepth values in the node's input queue that it has not finished now: those waiting
 *     and those it is processing (on Optimus, until the step that stores their results); {@code
 *     -1} where the media has no queue for the node (a chain on Liberty and Radiant runs in its
 *     caller's thread or inside the service it is linked into; a source has no input; generic
 *     services, combinators and timers have none on any media) or cannot
 *     read it now (Optimus with Redis unreachable); {@link Metrics#hasQueue} tells the two apart
 * @param missed for an event source, a timer or a combinator, the values the plain readers of
 *     its source missed (see {@link Reader#missed()}), as this process counted them: on Liberty and Radiant when a lagging
 *     reader next reads, on Optimus when a publish of this process trims a reader's list; 0 for
 *     the other nodes, whose inputs are queues, which never miss
 * @param processing how long the node took per value ({@code count} equals {@code valuesIn} once
 *     idle); a source's is how long its media took to accept each publish
 */
public record ServiceMetrics(
    String name,
    String pseudoname,
    String kind,
    long valuesIn,
    long valuesOut,
    long failures,
    long deadLetters,
    long queueDepth,
    long missed,
    ProcessingTimes processing) {

  /**
   * Checks the components.
   *
   * @param name the node's name
   * @param pseudoname the readable name, or {@code null}
   * @param kind the node's kind
   * @param valuesIn values given to the node
   * @param valuesOut values it gave out
   * @param failures values on which it threw
   * @param deadLetters values the media set aside
   * @param queueDepth values waiting now, {@code -1} if no queue
   * @param missed values its input missed
   * @param processing the time per value
   */
  public ServiceMetrics {
    Objects.requireNonNull(name, "name");
    Objects.requireNonNull(kind, "kind");
    Objects.requireNonNull(processing, "processing");
  }

  /** {@return the pseudoname if there is one, else the name: the label of drawings} */
  public String label() {
    return pseudoname != null ? pseudoname : name;
  }
}
