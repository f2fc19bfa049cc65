package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.RecordingOptions;
import dev.prime.optimus.FaultProxy;
import dev.prime.optimus.OptimusCore;
import dev.prime.test.CoreSetup;
import dev.prime.test.Media;
import dev.prime.test.PrimeTest;
import java.nio.file.Path;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Set;
import java.util.stream.Collectors;
import java.util.stream.IntStream;
import org.junit.jupiter.api.io.TempDir;

/**
 * What the README promises of a run on any media: its recording written ({@link
 * RecordingMcap#write}) and streamed ({@link RecordingMcap#stream}) as MCAP, one channel per
 * recorded service with its values, and replayed ({@link McapReplay}) into a diagram of the same
 * core, which computes what the recorded run computed; the file says which process recorded it,
 * and a written (not a streamed) channel how many values fell out of the recording's ring. Once on
 * each media.
 */
class RecordingMcapOnEveryMediaTest {
  private static final Duration WAIT = Duration.ofSeconds(20);
  private static final int VALUES = 10;

  @TempDir Path dir;

  record Pose(double x, double y) {}

  static final class Recorded implements CoreSetup {
    @Override
    public void configure(Media media, CoreConfig.Builder config) {
      config.recording(RecordingOptions.ring(64));
    }
  }

  /** Optimus on the class's Redis through a proxy that holds every reply back half a millisecond. */
  static final class RecordedOnSlowRedis implements CoreSetup {
    @Override
    public void configure(Media media, CoreConfig.Builder config) {
      new Recorded().configure(media, config);
    }

    @Override
    public PrimeCore optimus(CoreConfig config, String redisUrl) {
      return OptimusCore.builder().config(config).redis(FaultProxy.slowLinkTo(redisUrl)).build();
    }
  }

  private static Pose odometry(Integer ticks) {
    return new Pose(ticks, -ticks / 2.0);
  }

  private static List<Pose> take(Reader<Pose> reader) throws InterruptedException {
    List<Pose> taken = new ArrayList<>();
    for (int i = 0; i < VALUES; i++) {
      taken.add(reader.take(WAIT).orElseThrow(() -> new AssertionError("no value within " + WAIT)));
    }
    return taken;
  }

  @PrimeTest(media = Media.OPTIMUS, setup = RecordedOnSlowRedis.class)
  void aRunIsWrittenStreamedAndReplayedOnASlowRedis(PrimeCore core) throws Exception {
    aRunIsWrittenStreamedAndReplayedOnEveryMedia(core);
  }

  @PrimeTest(setup = Recorded.class)
  void aRunIsWrittenStreamedAndReplayedOnEveryMedia(PrimeCore core) throws Exception {
    EventBlock<Integer> ticks = new EventBlock<>();
    Reader<Pose> poses =
        core.source("ticks", "Wheel ticks", ticks)
            .then(core.chain("odometry", RecordingMcapOnEveryMediaTest::odometry))
            .reader();
    EventBlock<Integer> replayedTicks = new EventBlock<>();
    Reader<Pose> replayedPoses =
        core.source("replayed-ticks", replayedTicks)
            .then(core.chain("replayed-odometry", RecordingMcapOnEveryMediaTest::odometry))
            .reader();
    core.start();

    Path streamed = dir.resolve("streamed.mcap");
    List<Pose> computed;
    McapRecorder recorder =
        RecordingMcap.stream(core.recording(), streamed, McapWriterOptions.defaults());
    try (recorder) {
      for (int i = 1; i <= VALUES; i++) {
        ticks.publish(i);
      }
      computed = take(poses);
    }
    List<Integer> published = IntStream.rangeClosed(1, VALUES).boxed().toList();
    assertEquals(published.stream().map(RecordingMcapOnEveryMediaTest::odometry).toList(), computed);
    assertEquals(2 * VALUES, recorder.writtenCount(), "values streamed");
    assertEquals(0, recorder.droppedCount() + recorder.unwritableCount(), "values lost");

    Path written = dir.resolve("written.mcap");
    assertEquals(2 * VALUES, RecordingMcap.write(core.recording(), written));

    String process = ProcessHandle.current().pid() + "@";
    for (Path file : List.of(written, streamed)) {
      try (McapReader reader = McapReader.open(file)) {
        assertEquals(Set.of("ticks", "odometry"),
            reader.channels().stream().map(ChannelInfo::topic).collect(Collectors.toSet()),
            file + ": a channel per recorded service that ran");
        assertEquals(published,
            reader.messages("ticks", Integer.class).map(TypedMessage::value).toList(), file.toString());
        assertEquals(computed,
            reader.messages("odometry", Pose.class).map(TypedMessage::value).toList(), file.toString());
        ChannelInfo ticksChannel = reader.channel("ticks").orElseThrow();
        assertEquals("Wheel ticks", ticksChannel.metadata().get("prime.pseudoname"), file.toString());
        ChannelInfo odometry = reader.channel("odometry").orElseThrow();
        assertEquals("odometry", odometry.metadata().get("prime.service"), file.toString());
        String recordedBy = odometry.metadata().get(RecordingMcap.PROCESS_METADATA);
        assertEquals(process, recordedBy.substring(0, recordedBy.indexOf('@') + 1), file.toString());
        assertEquals(Long.toString(ProcessHandle.current().pid()),
            reader.metadata(RecordingMcap.PROCESS_METADATA).get(0).get("pid"), file.toString());
        // what fell out of the recording's rings: none here; a streamed channel has no such count
        assertEquals(file == written ? "0" : null, odometry.metadata().get("prime.dropped"), file.toString());
      }
    }

    ReplayResult fed =
        McapReplay.of(written).feed("ticks", replayedTicks, Integer.class).run();
    assertEquals(VALUES, fed.fed("ticks"));
    assertEquals(computed, take(replayedPoses), "the replay computes what the recorded run did");
  }
}
