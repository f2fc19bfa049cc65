package dev.prime;

/**
 * Receives the failures of asynchronous services: a block that threw while processing a value
 * of a source, or a step of a {@link GenericService} that threw. After the handler returns, the
 * service goes on with the next value (a generic service: with its next step, after its back-off).
 *
 * <p>Called on the service's thread; must be thread-safe if shared. An exception thrown by the
 * handler itself is logged and ignored, the same on every media: one ERROR line {@code the error
 * handler failed for service '<name>'} with the handler's exception and its stack trace, the
 * block's failure suppressed in it; the service goes on. A {@link VirtualMachineError} the
 * handler throws ends the service, as one its block throws.
 */
@FunctionalInterface
public interface ErrorHandler {

  /**
   * @param service the name of the chain whose block failed, as the user named it: for a chain
   *     linked to a source, the chain's name (not the name of the source it makes); for a linked
   *     chain, the innermost chain that failed; for a filter, flat-map or listener, its service
   *     name ({@code filter(source)}, ...); for a generic service, the name it was declared with
   * @param input the value being processed: the value the service took from its source, never
   *     {@code null}, as sources carry none. Media that fuse linked chains into one service
   *     (Liberty, Radiant) give the value that entered the linked chain; Optimus, which runs each
   *     chain as a service of its own, the value that entered the failing chain, which is {@code
   *     null} when the chain before it returned {@code null} (chains pass {@code null} between
   *     blocks, see {@link Block}). For a generic service, the {@link
   *     GenericService.Step} that failed. For a value the core's codec could not decode (see
   *     {@code error}), the bytes it could not decode (Optimus: the value's envelope)
   * @param error the block's (or generic service's step's) own throwable, never a {@link
   *     ChainFailedException} wrapper around a block's: any
   *     {@link Exception} or {@link Error} but a {@link VirtualMachineError}, which ends the service.
   *     A value whose copy the core's codec (a {@link ValueCodec}: {@link
   *     CoreConfig.Builder#copyValues}, or a distributed media's codec) could not decode is
   *     reported under the name of the service that read it, with a {@link PrimeException} that
   *     names that service and the codec and whose cause is the codec's exception; the service
   *     goes on with the next value
   */
  void handle(String service, Object input, Throwable error);
}
