package com.acme.robot

/* The types of one application package, for the codec's package and sealed allow-lists. */

/** A record of the package. */
@JvmRecord
public data class Reading(val sensor: String, val value: Double)

/** An enum of the package. */
public enum class Mode { IDLE, DRIVE }

/** A Kotlin data class (neither record nor enum) of the package. */
public data class Note(val text: String)

/** A sealed hierarchy: two records and a sealed subtype with one more. */
public sealed interface Command

/** Permitted by [Command]. */
@JvmRecord
public data class Move(val distance: Double) : Command

/** Permitted by [Command]. */
@JvmRecord
public data class Stop(val reason: String) : Command

/** Permitted by [Command], sealed itself. */
public sealed class Turn : Command

/** Permitted by [Turn]. */
public data class TurnLeft(val degrees: Int) : Turn()

/** One value of each concrete type of this package, by simple name, for the cross-loader probe. */
public object Samples {
    /** The sample values, in a fixed order. */
    @JvmStatic
    public fun all(): List<Any> = listOf(
        Reading("gyro", 0.25), Mode.DRIVE, Note("n"), Move(1.5), Stop("done"), TurnLeft(90),
    )
}
