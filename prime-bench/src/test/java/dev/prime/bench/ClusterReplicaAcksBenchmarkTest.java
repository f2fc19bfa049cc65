package dev.prime.bench;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.optimus.LocalRedisCluster;
import java.time.Duration;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.AfterAll;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;

/**
 * {@link ClusterReplicaAcksBenchmark} measures what it says, on a real local Redis Cluster: its
 * baseline ({@code replicaAcks = 0}) sends no {@code WAIT} to the topology's master, and with
 * {@code replicaAcks = 1} every call is confirmed by a replica (one {@code WAIT} per Redis
 * operation of the call: the caller's push and take, the service's take and step); both states
 * move their values intact and the flow loses none. One cluster serves every state here (the
 * benchmark starts one per trial).
 */
class ClusterReplicaAcksBenchmarkTest {
  private static final int CALLS = 20;

  @BeforeAll
  static void startCluster() {
    ClusterReplicaAcksBenchmark.OnCluster.shared = LocalRedisCluster.start(3, Duration.ofSeconds(5), false);
  }

  @AfterAll
  static void stopCluster() {
    ClusterReplicaAcksBenchmark.OnCluster.shared.close();
    ClusterReplicaAcksBenchmark.OnCluster.shared = null;
  }

  private static ClusterReplicaAcksBenchmark.Acks acks(int replicas) {
    ClusterReplicaAcksBenchmark.Acks acks = new ClusterReplicaAcksBenchmark.Acks();
    acks.replicaAcks = replicas;
    return acks;
  }

  /** Runs {@link #CALLS} calls with {@code replicas} acks; the master's WAIT count over them. */
  private static long waitsOverCalls(int replicas) {
    ClusterReplicaAcksBenchmark.ClusterCall call = new ClusterReplicaAcksBenchmark.ClusterCall();
    call.setUp(acks(replicas));
    try {
      for (int i = 0; i < CALLS; i++) {
        byte[] sent = call.value.clone();
        sent[0]++;
        assertArrayEquals(sent, call.call(), "call " + i + " returns its input");
      }
      return call.masterCalls("wait");
    } finally {
      call.tearDown();
    }
  }

  @Test
  @Timeout(value = 2, unit = TimeUnit.MINUTES)
  void theBaselineWaitsForNoReplicaAndReplicaAcksConfirmEveryOperationOfACall() {
    assertEquals(0, waitsOverCalls(0), "WAITs with replicaAcks 0");
    long waits = waitsOverCalls(1);
    // 4 operations per call (push, the service's take and step, the reply's take); a retried one adds
    assertTrue(waits >= 4L * CALLS && waits <= 5L * CALLS, "WAITs over " + CALLS + " calls with replicaAcks 1: " + waits);
  }

  @Test
  @Timeout(value = 2, unit = TimeUnit.MINUTES)
  void theFlowWithReplicaAcksPassesEveryValue() throws InterruptedException {
    ClusterReplicaAcksBenchmark.ClusterFlow flow = new ClusterReplicaAcksBenchmark.ClusterFlow();
    flow.setUp(acks(1));
    try {
      for (int i = 0; i < 3; i++) {
        assertEquals((long) ClusterReplicaAcksBenchmark.BATCH * ClusterReplicaAcksBenchmark.PAYLOAD, flow.passBatch());
      }
      assertTrue(flow.masterCalls("wait") > 0, "the flow's operations wait for the replica");
    } finally {
      flow.tearDown(); // fails if the reader missed a value
    }
  }
}
