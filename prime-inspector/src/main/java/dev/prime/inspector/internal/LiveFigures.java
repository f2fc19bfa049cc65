package dev.prime.inspector.internal;

import java.util.Map;

/**
 * Where the page's figures come from. {@link #sample()} is called by one thread, once per
 * sampling period; each call measures against the previous one.
 */
public interface LiveFigures {
  /** {@return the figures of every node it knows, by node name} */
  Map<String, NodeFigures> sample();

  /** {@return a sentence for the page: where the figures come from and what they lack} */
  String description();
}
