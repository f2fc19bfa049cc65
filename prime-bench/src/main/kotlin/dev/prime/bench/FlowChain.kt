package dev.prime.bench

import dev.prime.bench.PacketBlocks.Add
import kotlin.coroutines.Continuation
import kotlin.coroutines.EmptyCoroutineContext
import kotlin.coroutines.startCoroutine
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.flow
import kotlinx.coroutines.flow.map

/**
 * The benchmarked chain as a Kotlin Flow: a cold flow that emits the current input, with one
 * `map` per block, built once and collected once per transmission.
 *
 * Design: the flow is assembled once (as a chain is), so each transmission pays only what
 * collecting costs. Collection runs in a coroutine started on the calling thread with no
 * dispatcher: nothing in the flow suspends, so it finishes before [transmit] returns, which is the
 * cheapest way a synchronous (non-coroutine) caller can run a flow. Not thread-safe: one caller
 * at a time (the benchmark state is per thread).
 */
public class FlowChain(adders: Array<Add>) {
  private var input: Packet? = null
  private var output: Packet? = null
  private var failure: Throwable? = null
  private val chain: Flow<Packet>

  init {
    var assembled: Flow<Packet> = flow { emit(input!!) }
    for (adder in adders) {
      assembled = assembled.map { adder.process(it) }
    }
    chain = assembled
  }

  /**
   * Sends one packet through the flow and returns the output.
   *
   * @param packet the input
   * @return the output
   */
  public fun transmit(packet: Packet): Packet {
    input = packet
    output = null
    val collect: suspend () -> Unit = { chain.collect { output = it } }
    collect.startCoroutine(
        Continuation(EmptyCoroutineContext) { result -> failure = result.exceptionOrNull() })
    failure?.let { throw IllegalStateException("the flow failed", it) }
    return output ?: throw IllegalStateException("the flow suspended; it must run inline")
  }
}
