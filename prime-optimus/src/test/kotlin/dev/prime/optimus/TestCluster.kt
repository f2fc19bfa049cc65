package dev.prime.optimus

import java.time.Duration

/**
 * One local Redis Cluster (3 masters, 3 replicas, [LocalRedisCluster]) for the tests of this JVM
 * that only use it (the conformance kit, placement): each core is its own topology on it, in
 * the hash slot of its name. A shutdown hook stops the nodes and deletes their files.
 */
internal object TestCluster {
    val cluster: LocalRedisCluster by lazy {
        // no failover wanted here: a long node timeout, so a node starved of CPU is not failed over
        LocalRedisCluster.start(nodeTimeout = Duration.ofSeconds(5)).also { started ->
            Runtime.getRuntime().addShutdownHook(Thread({ started.close() }, "prime-test-cluster-stop"))
        }
    }

    val url: String get() = cluster.url
}
