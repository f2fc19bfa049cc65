package dev.prime.optimus

import redis.clients.jedis.CommandArguments
import redis.clients.jedis.Protocol
import redis.clients.jedis.args.Rawable
import redis.clients.jedis.commands.ProtocolCommand

/**
 * An argument Jedis writes as it is: Jedis copies every `byte[]` argument it is given (one copy of
 * each key and value per command), which on the call path was the largest share of what a call
 * allocates. The bytes must not change while the command is being written.
 */
internal class SentAsIs(private val bytes: ByteArray) : Rawable {
    override fun getRaw(): ByteArray = bytes

    override fun equals(other: Any?): Boolean = other is SentAsIs && other.bytes.contentEquals(bytes)

    override fun hashCode(): Int = bytes.contentHashCode()
}

/** [command] with [args], none of them copied: built once and sent many times where the arguments never change. */
internal fun commandOf(command: ProtocolCommand, vararg args: ByteArray): CommandArguments {
    val built = CommandArguments(command)
    for (arg in args) built.add(SentAsIs(arg))
    return built
}

/** `LEFT` and `RIGHT`, the ends of a list `LMOVE` and `BLMOVE` take from and push to. */
internal val LEFT: ByteArray = "LEFT".toByteArray(Charsets.US_ASCII)
internal val RIGHT: ByteArray = "RIGHT".toByteArray(Charsets.US_ASCII)

/** `MULTI` and `EXEC`, built once: they have no arguments. */
internal val MULTI: CommandArguments = commandOf(Protocol.Command.MULTI)
internal val EXEC: CommandArguments = commandOf(Protocol.Command.EXEC)
