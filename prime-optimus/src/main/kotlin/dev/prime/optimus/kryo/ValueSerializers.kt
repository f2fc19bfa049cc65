package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Serializer
import com.esotericsoftware.kryo.io.Input
import com.esotericsoftware.kryo.io.Output
import dev.prime.Repeat

/*
 * Serializers for built-in types Kryo cannot handle safely or at all by itself.
 */

/**
 * `boolean[]`: length, then one byte each. Kryo's own allocates the array before reading, so a
 * crafted length would cost memory; here the read goes through [BoundedInput.readBooleans].
 */
internal class BooleanArraySerializer : Serializer<BooleanArray>(false, false) {
    override fun write(kryo: Kryo, output: Output, array: BooleanArray) {
        output.writeVarInt(array.size, true)
        output.writeBooleans(array, 0, array.size)
    }

    override fun read(kryo: Kryo, input: Input, type: Class<out BooleanArray>): BooleanArray =
        input.readBooleans(input.readVarInt(true))
}

/**
 * Prime's [Repeat] (a final class with a private constructor): whether to run again, then the
 * next input or the conclusion with its class id. Reads through [Repeat.again]/[Repeat.stop].
 */
internal class RepeatSerializer : Serializer<Repeat<*, *>>(false, true) {
    override fun write(kryo: Kryo, output: Output, repeat: Repeat<*, *>) {
        output.writeBoolean(repeat.isAgain)
        kryo.writeClassAndObject(output, if (repeat.isAgain) repeat.next() else repeat.conclusion())
    }

    override fun read(kryo: Kryo, input: Input, type: Class<out Repeat<*, *>>): Repeat<*, *> {
        val again = input.readBoolean()
        val value: Any? = kryo.readClassAndObject(input)
        return if (again) Repeat.again<Any?, Any?>(value) else Repeat.stop<Any?, Any?>(value)
    }
}

/**
 * `String` as its UTF-8 byte count and bytes. The JDK's own UTF-8 coding (vectorized for ASCII
 * and Latin-1 text) is several times faster than Kryo's char-by-char loop for longer strings,
 * for one temporary array on write. The count is checked against the remaining bytes before the
 * string is made.
 */
internal class Utf8StringSerializer : Serializer<String>(false, true) {
    override fun write(kryo: Kryo, output: Output, string: String) {
        val bytes = string.toByteArray(Charsets.UTF_8)
        output.writeVarInt(bytes.size, true)
        output.writeBytes(bytes)
    }

    override fun read(kryo: Kryo, input: Input, type: Class<out String>): String {
        val length = input.readVarInt(true)
        input.requireAvailable(length, 1, "a string")
        val start = input.position()
        val string = String(input.buffer, start, length, Charsets.UTF_8)
        input.setPosition(start + length)
        return string
    }
}
