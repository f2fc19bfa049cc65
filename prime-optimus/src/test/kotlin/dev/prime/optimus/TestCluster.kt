package dev.prime.optimus

/**
 * One local Redis Cluster (3 masters, 3 replicas, [LocalRedisCluster]) for the tests of this JVM
 * that only use it (the conformance kit, placement): each core is its own topology on it, in
 * the hash slot of its name. A shutdown hook stops the nodes and deletes their files.
 */
internal object TestCluster {
    val cluster: LocalRedisCluster by lazy {
        LocalRedisCluster.start().also { started ->
            Runtime.getRuntime().addShutdownHook(Thread({ started.close() }, "prime-test-cluster-stop"))
        }
    }

    val url: String get() = cluster.url
}
