package dev.prime.optimus

import com.esotericsoftware.kryo.DefaultSerializer
import com.esotericsoftware.kryo.serializers.JavaSerializer
import java.io.ObjectInputStream
import java.io.Serializable
import java.util.concurrent.atomic.AtomicBoolean

/* Application-like types for the codec tests. */

@JvmRecord
internal data class Pose(val x: Double, val y: Double, val heading: Double)

/** A record with a nested registered record, a List of them, a Map and a nullable field. */
@JvmRecord
internal data class Route(
    val name: String,
    val start: Pose,
    val waypoints: List<Pose>,
    val speeds: Map<String, Int>,
    val note: String?,
)

/** A record with an open component, to carry anything (registered or not) inside. */
@JvmRecord
internal data class Parcel(val id: Long, val body: Any?)

/** A record with a byte[] payload (equality by content written by hand). */
@JvmRecord
internal data class Packet(val seq: Int, val payload: ByteArray) {
    override fun equals(other: Any?): Boolean =
        other is Packet && seq == other.seq && payload.contentEquals(other.payload)

    override fun hashCode(): Int = 31 * seq + payload.contentHashCode()
}

/** A classic POJO: no-arg constructor and mutable fields. */
internal class Counter() {
    var name: String = ""
    var count: Long = 0
    var samples: MutableList<Int> = ArrayList()

    constructor(name: String, count: Long, samples: List<Int>) : this() {
        this.name = name
        this.count = count
        this.samples = ArrayList(samples)
    }

    override fun equals(other: Any?): Boolean =
        other is Counter && name == other.name && count == other.count && samples == other.samples

    override fun hashCode(): Int = name.hashCode()
}

/** A Kotlin data class: no no-arg constructor. */
internal data class Label(val text: String, val weight: Int)

internal enum class Colour { RED, GREEN, BLUE }

/** Never registered anywhere. */
internal data class Stranger(val secret: String)

/**
 * A Serializable class whose readObject has a visible side effect: the canary for "Java
 * serialization never runs on decode".
 */
internal class Tripwire(var payload: String = "") : Serializable {
    private fun readObject(stream: ObjectInputStream) {
        TRIGGERED.set(true)
        stream.defaultReadObject()
    }

    override fun equals(other: Any?): Boolean = other is Tripwire && payload == other.payload

    override fun hashCode(): Int = payload.hashCode()

    companion object {
        private const val serialVersionUID: Long = 1L

        @JvmField
        val TRIGGERED: AtomicBoolean = AtomicBoolean(false)
    }
}

/** Asks Kryo for Java serialization: the codec must refuse to register it. */
@DefaultSerializer(JavaSerializer::class)
internal class AsksForJavaSerialization : Serializable {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

internal interface Shape

internal abstract class AbstractShape : Shape
