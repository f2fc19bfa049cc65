package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.mcap.ChannelInfo;
import dev.prime.mcap.McapMerge;
import dev.prime.mcap.McapMessage;
import dev.prime.mcap.McapReader;
import dev.prime.mcap.PythonMcapCheck;
import dev.prime.mcap.RecordingMcap;
import java.io.IOException;
import java.io.OutputStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.io.TempDir;

/**
 * A robot run recorded across two processes: a {@link RobotWorker} JVM (a real second process)
 * hosts the planner and records it, the robot (this JVM) hosts the rest of the topology and
 * records its sources and chains; both are Optimus cores on the worker's embedded Redis. The two
 * files are merged with {@link McapMerge}; the merged file has one channel per recorded service
 * with the counts of both files added up, in log-time order, read by {@link McapReader} and by the
 * Python {@code mcap} package; replayed on Liberty without {@code --goal} or {@code --trace-every}
 * (both come from the file), it prints the recorded run's trace, every step.
 */
class MergedRecordingTest {
  private static final String GOAL = "1,0.5";
  private static final String CORE = "robot-merge";

  @TempDir Path dir;

  /** The worker JVM with its output lines collected by a daemon thread. */
  /** A worker JVM hosting and recording the planner into {@code record}. */
  private static WorkerJvm startWorker(Path record, boolean stdinClosed) throws IOException {
    return WorkerJvm.start(
        stdinClosed,
        "--hosts", "planner", "--goal", GOAL, "--name", CORE, "--record", record.toString());
  }

  private static Map<String, Long> counts(Path file) throws IOException {
    Map<String, Long> counts = new TreeMap<>();
    try (McapReader reader = McapReader.open(file)) {
      for (ChannelInfo channel : reader.channels()) {
        counts.put(channel.topic(), reader.messageCount(channel.topic()));
      }
    }
    return counts;
  }

  @Test
  @Timeout(value = 8, unit = TimeUnit.MINUTES) // a first pip install may take minutes
  void twoProcessesRecordWhatTheyHostAndTheMergedFileReplaysTheRun() throws Exception {
    Path robotFile = dir.resolve("robot.mcap");
    Path workerFile = dir.resolve("worker.mcap");
    WorkerJvm worker = startWorker(workerFile, false);
    RecordReplayTest.Run recorded;
    try {
      String ready = "READY robot worker hosting [planner] of core '" + CORE + "' on ";
      String redisUrl = worker.awaitLine(ready, 60).substring(ready.length());
      recorded =
          RecordReplayTest.main(
              "--media", "optimus", "--redis", redisUrl, "--remote", "planner", "--name", CORE,
              "--goal", GOAL, "--trace-every", "1", "--record", robotFile.toString());
      assertEquals(0, recorded.code(), recorded.out() + recorded.err() + worker.output());

      OutputStream stdin = worker.process().getOutputStream();
      stdin.write("STOP\n".getBytes(StandardCharsets.UTF_8));
      stdin.flush();
      assertTrue(worker.process().waitFor(60, TimeUnit.SECONDS), "still running: " + worker.output());
      assertEquals(0, worker.process().exitValue(), worker.output());
      assertTrue(worker.output().contains("recorded "), worker.output());
    } finally {
      worker.process().destroyForcibly();
    }
    int steps = recorded.trace().size();
    assertTrue(steps > 50, recorded.out());

    // each process recorded what it hosts: the robot its encoders, odometry and pid, the worker the planner
    Map<String, Long> robotCounts = counts(robotFile);
    Map<String, Long> workerCounts = counts(workerFile);
    assertEquals(List.of("planner"), List.copyOf(workerCounts.keySet()));
    assertEquals(List.of("encoders", "odometry", "pid"), List.copyOf(robotCounts.keySet()));
    long planned = workerCounts.get("planner");
    assertEquals((long) steps, robotCounts.get("encoders"));
    assertEquals((long) steps, robotCounts.get("odometry"));
    // the guard sends the last estimate (arrived) to its substitute, not to planner>pid
    assertTrue(planned == steps - 1 || planned == steps, planned + " of " + steps);
    assertEquals(planned, robotCounts.get("pid"));

    Path merged = dir.resolve("run.mcap");
    McapMerge.Result result = McapMerge.merge(List.of(robotFile, workerFile), merged);

    Map<String, Long> expected = new TreeMap<>(robotCounts);
    workerCounts.forEach((topic, count) -> expected.merge(topic, count, Long::sum));
    long total = 2L * steps + 2L * planned;
    assertEquals(total, result.messages());
    assertEquals(expected, counts(merged));
    try (McapReader reader = McapReader.open(merged)) {
      reader.verify();
      List<McapMessage> messages = reader.messages().toList();
      assertEquals(total, messages.size());
      for (int i = 1; i < messages.size(); i++) {
        assertTrue(messages.get(i - 1).logTime() <= messages.get(i).logTime(), "log time order at " + i);
      }
      // causality across processes: the planner's k-th output is stamped after the robot's k-th odometry
      List<Long> odometry = reader.messages("odometry").map(McapMessage::logTime).toList();
      List<Long> planner = reader.messages("planner").map(McapMessage::logTime).toList();
      for (int k = 0; k < planner.size(); k++) {
        assertTrue(odometry.get(k) <= planner.get(k), "step " + k);
      }
      List<Map<String, String>> processes = reader.metadata(RecordingMcap.PROCESS_METADATA);
      assertEquals(2, processes.size(), processes.toString());
      assertNotEquals(processes.get(0).get("pid"), processes.get(1).get("pid"));
      assertEquals(Long.toString(ProcessHandle.current().pid()), processes.get(0).get("pid"));
      assertEquals(Long.toString(worker.process().pid()), processes.get(1).get("pid"));
      Map<String, String> run = reader.metadata(RunArguments.METADATA).get(0);
      assertEquals("1.0,0.5", run.get("goal"));
      assertEquals("planner", run.get("remote"));
      assertEquals("planner", reader.metadata(RunArguments.WORKER_METADATA).get(0).get("hosts"));
      assertTrue(reader.channel("planner").orElseThrow().metadata().get(RecordingMcap.PROCESS_METADATA)
          .startsWith(worker.process().pid() + "@"));
    }

    PythonMcapCheck python = PythonMcapCheck.installOrSkip();
    JsonNode check = python.check(merged, dir);
    Map<String, Long> statistics = new TreeMap<>();
    Map<String, Long> read = new TreeMap<>();
    check.get("channels").properties().forEach(e -> {
      statistics.put(e.getKey(), e.getValue().get("statistics_count").asLong());
      read.put(e.getKey(), e.getValue().get("read_count").asLong());
    });
    assertEquals(expected, statistics, check.toString());
    assertEquals(expected, read);
    assertTrue(check.get("log_time_sorted").asBoolean());
    assertEquals(List.of(), new ObjectMapper().convertValue(check.get("schema_errors"), List.class));

    // the merged file replays the run on Liberty: goal and trace interval come from the file
    RecordReplayTest.Run replay = RecordReplayTest.main("--media", "liberty", "--replay", merged.toString());
    assertEquals(0, replay.code(), replay.out() + replay.err());
    assertTrue(replay.out().contains("from the recording: --goal 1.0,0.5"), replay.out());
    assertEquals(recorded.trace(), replay.trace());
  }

  /** Under systemd or Docker a worker is stopped by SIGTERM: it still writes its recording. */
  @Test
  void aWorkerStoppedBySigtermWritesItsRecording() throws Exception {
    Path workerFile = dir.resolve("worker.mcap");
    WorkerJvm worker = startWorker(workerFile, true);
    try {
      String ready = "READY robot worker hosting [planner] of core '" + CORE + "' on ";
      String redisUrl = worker.awaitLine(ready, 60).substring(ready.length());
      RecordReplayTest.Run run =
          RecordReplayTest.main(
              "--media", "optimus", "--redis", redisUrl, "--remote", "planner", "--name", CORE,
              "--goal", GOAL, "--steps", "20");
      assertEquals(1, run.code(), "20 steps do not reach the goal: " + run.out() + run.err());

      assertTrue(worker.process().toHandle().destroy(), "SIGTERM could not be sent");
      assertTrue(worker.process().waitFor(60, TimeUnit.SECONDS), "still running: " + worker.output());
      assertEquals(143, worker.process().exitValue(), worker.output());
      assertTrue(worker.output().contains("recorded 20 values to " + workerFile + ": planner 20"),
          worker.output());
    } finally {
      worker.process().destroyForcibly();
    }
    try (McapReader reader = McapReader.open(workerFile)) {
      assertEquals(20, reader.messageCount("planner"));
      assertEquals("planner", reader.metadata(RunArguments.WORKER_METADATA).get(0).get("hosts"));
    }
  }
}
