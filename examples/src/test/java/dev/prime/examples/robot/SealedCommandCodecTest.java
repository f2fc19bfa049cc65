package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.optimus.KryoCodec;
import java.util.List;
import org.junit.jupiter.api.Test;

/** A Java sealed interface allows every record it permits, and nothing else, in one line. */
class SealedCommandCodecTest {

  /** What an operator may send the robot. */
  sealed interface Command permits Go, Halt {}

  /** Drive to a goal. */
  record Go(Goal goal) implements Command {}

  /** Stop where it is. */
  record Halt(String reason) implements Command {}

  /** Not a command. */
  record Chatter(String text) {}

  @Test
  void allowingTheSealedInterfaceAllowsTheRecordsItPermits() {
    KryoCodec codec =
        KryoCodec.builder().learnRecordsAndEnums(false).allow(Command.class).allow(Goal.class).build();
    for (Command command : List.of(new Go(new Goal(1, 2)), new Halt("operator"))) {
      assertEquals(command, codec.decode(codec.encode(command)));
    }
    IllegalArgumentException e =
        assertThrows(IllegalArgumentException.class, () -> codec.encode(new Chatter("hi")));
    assertTrue(
        e.getMessage().contains("KryoCodec.builder().allow(SealedCommandCodecTest.Chatter.class)"),
        e.getMessage());
  }
}
