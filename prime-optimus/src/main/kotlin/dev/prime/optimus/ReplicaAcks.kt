package dev.prime.optimus

import redis.clients.jedis.Jedis
import java.time.Duration

/**
 * How many replicas must confirm every Redis operation of a core before it counts as done
 * (`OptimusCore.Builder.replicaAcks`): after each operation the connection sends `WAIT replicas
 * timeout`, which returns once that many replicas have everything the connection wrote (at once
 * if it wrote nothing they lack). Redis replicates asynchronously: without this, a value a
 * master acknowledged can be missing on the replica that a failover promotes.
 */
internal class ReplicaAcks(val replicas: Int, val timeout: Duration) {
    /**
     * Waits until [replicas] replicas have what [jedis] wrote, at most [timeout] and never past
     * [deadline] (a [System.nanoTime]; `null`: none).
     *
     * @throws ReplicaAcksMissing if fewer confirmed in time
     */
    fun confirm(jedis: Jedis, deadline: Long?) {
        var millis = timeout.toMillis()
        // at least 1 ms: WAIT with 0 would wait forever
        if (deadline != null) millis = minOf(millis, ceilMillis(deadline - System.nanoTime()))
        val acked = jedis.waitReplicas(replicas, millis)
        if (acked < replicas) {
            throw ReplicaAcksMissing(
                "Redis confirmed an operation on $acked of the $replicas replicas OptimusCore.Builder.replicaAcks asks " +
                    "for within $millis ms: it is on the master but might not survive a failover, so it counts as " +
                    "failed and is retried. Does the master have $replicas replicas connected and keeping up (INFO " +
                    "replication)?",
            )
        }
    }
}

/**
 * Too few replicas confirmed an operation within the time allowed ([ReplicaAcks]): handled as a
 * connection broken after the command ran (it may or may not survive a failover), so it is
 * retried the way such an operation is.
 */
internal class ReplicaAcksMissing(message: String) : RuntimeException(message)
