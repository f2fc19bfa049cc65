package dev.prime.optimus

import com.acme.robot.Command
import com.acme.robot.Samples

/**
 * Runs in a class loader of its own (see [KryoCodecIdentityTest]): builds the shared test codec
 * there and encodes the samples in a given order. Only JDK types cross the loader boundary.
 */
public object CrossLoaderProbe {

    /** The codec every side of the identity test builds: a sealed type, a package and learning. */
    public fun codec(): KryoCodec {
        val thread = Thread.currentThread()
        val previous = thread.contextClassLoader
        thread.contextClassLoader = CrossLoaderProbe::class.java.classLoader
        try {
            return KryoCodec.builder().allow(Command::class.java).allowPackage("com.acme.robot").build()
        } finally {
            thread.contextClassLoader = previous
        }
    }

    /** The sample values, then a learned record of another package, in a fixed order. */
    public fun values(): List<Any> = Samples.all() + Pose(1.0, -2.0, 0.5)

    /**
     * The codec's fingerprint, then the bytes of each value of [values] (in that order), having
     * encoded them in the order [order] gives (indexes into [values]).
     */
    @JvmStatic
    public fun encode(order: IntArray): List<Any> {
        val codec = codec()
        val values = values()
        val bytes = arrayOfNulls<ByteArray>(values.size)
        for (index in order) bytes[index] = codec.encode(values[index])
        return listOf<Any>(codec.fingerprint()) + bytes.map { it!! }
    }
}
