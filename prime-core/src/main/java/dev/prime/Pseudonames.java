package dev.prime;


/** Records a chain or source with a pseudoname, for {@link PrimeCore}'s creating methods. */
final class Pseudonames {
  private Pseudonames() {}

  /** Records a chain made of {@code block} named {@code name} with a checked pseudoname. */
  static String record(TopologyRecorder model, String name, String pseudoname, Block<?, ?> block) {
    synchronized (model) {
      String claimed = model.blockChain(name, block);
      model.pseudoname(claimed, pseudoname);
      return claimed;
    }
  }

  /** Records a source fed by {@code events} named {@code name} with a checked pseudoname. */
  static String record(
      TopologyRecorder model, String name, String pseudoname, EventBlock<?> events) {
    synchronized (model) {
      String claimed = model.eventSource(name, events);
      model.pseudoname(claimed, pseudoname);
      return claimed;
    }
  }
}
