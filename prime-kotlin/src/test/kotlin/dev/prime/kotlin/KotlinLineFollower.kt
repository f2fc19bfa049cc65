package dev.prime.kotlin

import dev.prime.Block
import dev.prime.PrimeCore
import dev.prime.Source
import dev.prime.Tick
import dev.prime.Tuple2
import java.time.Duration
import kotlin.math.cos
import kotlin.math.sin

/** A gyro reading: [millis] of the core's clock since start, [yawRate] in rad/s. */
internal data class GyroReading(val millis: Long, val yawRate: Double)

/** A line-sensor reading: [millis] of the core's clock since start, [offset] in metres. */
internal data class LineReading(val millis: Long, val offset: Double)

/** A steering command made from a gyro and a line reading of the given times. */
internal data class Steering(val gyroMillis: Long, val lineMillis: Long, val turnRate: Double)

/**
 * The line follower's sensor fusion in Kotlin, as the README shows it between the markers: the
 * same diagram as the Java `LineFollower` of the examples (gyro at 100 Hz, line sensor at 20 Hz,
 * each gyro reading fused with the latest line reading, a PD controller), with the simulated
 * sensors and the controller written as lambdas.
 */
internal object KotlinLineFollower {
    fun gyroAt(millis: Long) = GyroReading(millis, 0.5 * cos(millis / 1000.0))

    fun lineAt(millis: Long) = LineReading(millis, 0.1 * sin(millis / 1000.0))

    fun declare(core: PrimeCore): Source<Steering> {
        // kotlin-fusion:begin
        val gyro: Source<GyroReading> =
            core.timer("gyro-clock", Duration.ofMillis(10))                  // 100 Hz
                .then(core.chain("gyro", Block { t: Tick -> gyroAt(t.count() * 10) }))
        val line: Source<LineReading> =
            core.timer("line-clock", Duration.ofMillis(50))                  // 20 Hz
                .then(core.chain("line", Block { t: Tick -> lineAt(t.count() * 50) }))
        val steering: Source<Steering> =
            gyro.withLatestFrom(line)            // each gyro reading + the latest line reading
                .then(core.chain("steer", Block { fused: Tuple2<GyroReading, LineReading> ->
                    val (g, l) = fused.first() to fused.second()
                    Steering(g.millis, l.millis, 2.0 * l.offset - 0.3 * g.yawRate)
                }))
        // kotlin-fusion:end
        return steering
    }
}
