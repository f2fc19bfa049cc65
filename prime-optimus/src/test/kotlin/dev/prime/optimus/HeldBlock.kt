package dev.prime.optimus

import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * Called in a block: counts [entered] down, then waits for [release], so a test holds a service
 * inside its block while it changes Redis under it. Fails the block if the test does not release
 * it within [patience].
 */
internal fun holdInBlock(entered: CountDownLatch, release: CountDownLatch, patience: Duration = Duration.ofSeconds(20)) {
    entered.countDown()
    check(release.await(patience.seconds, TimeUnit.SECONDS)) { "the test did not release the block within $patience" }
}
