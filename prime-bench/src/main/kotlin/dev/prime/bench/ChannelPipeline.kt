package dev.prime.bench

import dev.prime.bench.PacketBlocks.Add
import java.util.concurrent.Executors
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.asCoroutineDispatcher
import kotlinx.coroutines.cancel
import kotlinx.coroutines.channels.Channel
import kotlinx.coroutines.launch

/**
 * The benchmarked chain behind a Kotlin Channel: the caller sends packets, one consumer coroutine
 * on a thread of its own receives each, runs the blocks and counts the output in [arrivals].
 *
 * Design: one producer thread (the caller) and one consumer thread, as one Prime source with a
 * linked chain has; the channel's capacity holds a whole batch, so [send] never has to suspend
 * and can be called from plain Java code. The consumer's dispatcher is a single daemon thread
 * named `bench-channel`, closed by [close].
 */
public class ChannelPipeline(private val adders: Array<Add>, capacity: Int) : AutoCloseable {
  /** Counts the packets that came out of the chain, and sums their values. */
  public val arrivals: Arrivals = Arrivals()

  private val executor =
      Executors.newSingleThreadExecutor { task ->
        Thread(task, "bench-channel").apply { isDaemon = true }
      }
  private val scope = CoroutineScope(executor.asCoroutineDispatcher())
  private val channel = Channel<Packet>(capacity)

  init {
    scope.launch {
      for (packet in channel) {
        arrivals.arrive(ChainShapes.runDirect(adders, packet).value)
      }
    }
  }

  /**
   * Hands a packet to the consumer.
   *
   * @param packet the input
   * @throws IllegalStateException if the channel is full (more in flight than its capacity)
   */
  public fun send(packet: Packet) {
    val result = channel.trySend(packet)
    check(result.isSuccess) { "channel full or closed: $result; send at most capacity packets" }
  }

  override fun close() {
    channel.close()
    scope.cancel()
    executor.shutdownNow()
  }
}
