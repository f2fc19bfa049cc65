/**
 * The diagram a core was given, as data: {@link dev.prime.topology.Topology} is an immutable
 * snapshot of the chains, sources, links, templates and readers declared on a {@link
 * dev.prime.PrimeCore}, with their names, which of them are services and where each service is
 * hosted. Get one with {@link dev.prime.PrimeCore#topology()}; draw it with {@link
 * dev.prime.topology.Topology#toMermaid()} or {@link dev.prime.topology.Topology#toDot()}.
 *
 * <p>The same declarations give the same topology on every media: names are made in one place,
 * in declaration order, so a diagram drawn from a Liberty core is the diagram of the same
 * program on Radiant or Optimus.
 */
package dev.prime.topology;
