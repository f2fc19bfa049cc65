package dev.prime;

/**
 * Sees each value of a {@link Recording} as it is recorded (see {@link
 * Recording#subscribe(RecordingListener)}): for a continuous writer to disk, which keeps every
 * value where the recording's rings keep only the latest few per name.
 *
 * <p>Threading contract: {@link #recorded} is called on the recording thread (the thread that
 * published the value or ran the chain: a service thread, a caller of {@code toBlock()}, a
 * coroutine), inside the ring's monitor of that name, so the values of one name arrive in
 * sequence order while values of different names may arrive concurrently. It must return quickly
 * and never block (hand the value to a bounded queue and drop when it is full): the controller
 * waits for it. What it throws (an exception, checked or not, or an {@link Error} but a {@link
 * VirtualMachineError}) is caught, counted in {@link Recording.Subscription#failures()}, and does
 * not reach the controller.
 */
@FunctionalInterface
public interface RecordingListener {
  /**
   * Called once per recorded value, after the value is in its ring.
   *
   * @param value the value with its name, pseudoname, sequence number and time stamps
   */
  void recorded(RecordedValue<Object> value);
}
