package dev.prime;

import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.List;
import java.util.function.Consumer;
import java.util.function.Function;

/**
 * What a combinator of several sources does with each value of one of its inputs: which values it
 * emits for it. The pairing rules of {@link PrimeCore#combineLatest}, {@link PrimeCore#zip},
 * {@link PrimeCore#merge} and {@link Source#withLatestFrom}, as plain state machines.
 *
 * <p>Not thread-safe: {@link CombinedInputs} calls {@link #accept} under its lock, one value at a
 * time, and publishes what it emits under the same lock, so outputs leave in the order the values
 * were accepted.
 */
interface Pairing {

  /**
   * Takes one value of input {@code input} (0 for the first) and emits what it makes.
   *
   * @param input which input the value came from
   * @param value the value, never {@code null}
   * @param emit receives each output, in order
   */
  void accept(int input, Object value, Consumer<Object> emit);

  /** Every value of every input, as it comes. */
  static Pairing merge() {
    return (input, value, emit) -> emit.accept(value);
  }

  /**
   * Each value with the latest value of every other input, once every input has one: the values
   * before that only update the latest.
   */
  static Pairing combineLatest(int inputs, Function<Object[], Object> tuple) {
    Object[] latest = new Object[inputs];
    int[] missing = {inputs};
    return (input, value, emit) -> {
      if (latest[input] == null) {
        missing[0]--;
      }
      latest[input] = value;
      if (missing[0] == 0) {
        emit.accept(tuple.apply(latest.clone()));
      }
    };
  }

  /**
   * The n-th value of every input together. Each input keeps at most {@code limit} values not yet
   * paired; a value that finds its input full drops that input's oldest unpaired value, reported
   * to {@code dropped}.
   */
  static Pairing zip(
      int inputs, int limit, Function<Object[], Object> tuple, Consumer<Integer> dropped) {
    List<ArrayDeque<Object>> waiting = new ArrayList<>(inputs);
    for (int i = 0; i < inputs; i++) {
      waiting.add(new ArrayDeque<>());
    }
    return (input, value, emit) -> {
      ArrayDeque<Object> own = waiting.get(input);
      if (own.size() >= limit) {
        own.poll();
        dropped.accept(input);
      }
      own.add(value);
      for (ArrayDeque<Object> queue : waiting) {
        if (queue.isEmpty()) {
          return;
        }
      }
      Object[] values = new Object[inputs];
      for (int i = 0; i < inputs; i++) {
        values[i] = waiting.get(i).poll();
      }
      emit.accept(tuple.apply(values));
    };
  }

  /**
   * Each value of input 0 with the latest value of input 1; values of input 0 before input 1 has
   * one are dropped; values of input 1 emit nothing.
   */
  static Pairing withLatestFrom() {
    Object[] latest = new Object[1];
    return (input, value, emit) -> {
      if (input == 1) {
        latest[0] = value;
      } else if (latest[0] != null) {
        emit.accept(new Tuple2<>(value, latest[0]));
      }
    };
  }
}
