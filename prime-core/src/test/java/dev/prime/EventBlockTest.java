package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.util.List;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.function.Consumer;
import org.junit.jupiter.api.Test;

/** The event block on its own, without any core: subscriptions and their order. */
class EventBlockTest {

  /**
   * {@link EventBlock.Subscription#close()}: "Stops delivering values to this subscriber.
   * Idempotent." One consumer subscribed twice has two subscriptions: closing one of them, twice,
   * stops one delivery only, and the other subscription goes on delivering; the subscribers are
   * called in subscription order.
   */
  @Test
  void closingASubscriptionTwiceEndsThatSubscriptionOnly() {
    EventBlock<Integer> events = new EventBlock<>();
    List<String> heard = new CopyOnWriteArrayList<>();
    Consumer<Integer> twice = x -> heard.add("twice " + x);
    EventBlock.Subscription first = events.subscribe(twice);
    events.subscribe(x -> heard.add("other " + x));
    events.subscribe(twice);

    events.publish(1);
    assertEquals(List.of("twice 1", "other 1", "twice 1"), heard, "in subscription order");

    heard.clear();
    first.close();
    first.close(); // idempotent: the second subscription of the same consumer stays
    events.publish(2);
    assertEquals(List.of("other 2", "twice 2"), heard);
  }
}
