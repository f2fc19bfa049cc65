package dev.prime.bench.report;

import java.io.IOException;
import java.io.InputStream;
import java.io.PrintStream;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Comparator;
import java.util.Deque;
import java.util.HashMap;
import java.util.HashSet;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.Set;
import java.util.stream.Stream;
import javax.xml.stream.XMLInputFactory;
import javax.xml.stream.XMLStreamException;
import javax.xml.stream.XMLStreamReader;

/**
 * Reads the compilation logs of benchmark forks ({@code -XX:+LogCompilation}, one file per JVM)
 * and says, for every C2 compilation of a JMH measurement loop or of a Prime class, how many calls
 * into the benchmark's blocks it inlined and which calls to Prime classes it did not inline, with
 * C2's reason. Deterministic evidence of where inlining stops, whatever the machine's load.
 *
 * <pre>{@code
 * java -cp prime-bench/target/benchmarks.jar dev.prime.bench.report.InliningReport DIR
 * }</pre>
 *
 * <p>A block call is a call from outside the blocks' package into it (a block's bridge method
 * calling its own typed method is not counted twice). {@code prime-bench/inlining-report} runs a
 * benchmark with the right flags and then this report.
 */
public final class InliningReport {
  /** Where the benchmark's blocks live. */
  static final String BLOCKS = "dev.prime.bench.PacketBlocks";

  private InliningReport() {}

  /**
   * One C2 compilation.
   *
   * @param stamp seconds since the JVM started, when the compilation began
   * @param id the compile id
   * @param osr whether it is an on-stack-replacement compilation (a loop entered while running)
   * @param method the compiled method, {@code Class::name}
   * @param blockCalls calls into the blocks that were inlined
   * @param refused calls into Prime classes that were not inlined, each with C2's reason
   * @param replaced whether the JVM later threw this code away (made not entrant)
   * @param codeBytes size of the compiled instructions (what C2 compares with {@code
   *     InlineSmallCode}, 2500 by default, before inlining this method into a caller), or -1
   */
  record Compilation(
      double stamp,
      String id,
      boolean osr,
      String method,
      int blockCalls,
      List<String> refused,
      boolean replaced,
      int codeBytes) {

    /** One line: when, which, what was inlined and what was not. */
    String describe() {
      return String.format(
          "%7.3f s  c2 %-5s%s %s (%s): %d block calls inlined%s%s",
          stamp,
          id,
          osr ? " osr" : "    ",
          method,
          codeBytes < 0 ? "code size unknown" : codeBytes + " B of code",
          blockCalls,
          refused.isEmpty() ? "" : "; not inlined: " + String.join(", ", refused),
          replaced ? "  [later made not entrant]" : "");
    }
  }

  /**
   * Prints the report for every {@code *.log} file in a directory.
   *
   * @param args the directory
   * @throws IOException if a file cannot be read
   * @throws XMLStreamException if a file is not a compilation log
   */
  public static void main(String[] args) throws IOException, XMLStreamException {
    if (args.length != 1) {
      throw new IllegalArgumentException(
          "usage: InliningReport DIR (a directory of -XX:+LogCompilation files, one per fork)");
    }
    print(Path.of(args[0]), System.out);
  }

  /**
   * Prints the report for every {@code *.log} file in a directory, oldest first (one per fork).
   *
   * @param directory the logs
   * @param out where to print
   * @throws IOException if a file cannot be read
   * @throws XMLStreamException if a file is not a compilation log
   */
  static void print(Path directory, PrintStream out) throws IOException, XMLStreamException {
    List<Path> logs;
    try (Stream<Path> files = Files.list(directory)) {
      logs =
          files
              .filter(p -> p.getFileName().toString().endsWith(".log"))
              .sorted(Comparator.comparing(InliningReport::modified))
              .toList();
    }
    if (logs.isEmpty()) {
      throw new IllegalArgumentException(
          "no .log files in " + directory + ": run the benchmark with -XX:+LogCompilation "
              + "-XX:LogFile=" + directory + "/compilation-%p.log");
    }
    int fork = 0;
    for (Path log : logs) {
      out.println("fork " + ++fork + " (" + log.getFileName() + ")");
      try (InputStream in = Files.newInputStream(log)) {
        for (Compilation c : read(in)) {
          out.println("  " + c.describe());
        }
      }
    }
  }

  private static long modified(Path file) {
    try {
      return Files.getLastModifiedTime(file).toMillis();
    } catch (IOException e) {
      throw new IllegalStateException("cannot read the time of " + file, e);
    }
  }

  /**
   * The C2 compilations of JMH loops and Prime classes in one compilation log, by start time.
   *
   * @param log the log's content
   * @return the compilations
   * @throws XMLStreamException if it is not a compilation log
   */
  static List<Compilation> read(InputStream log) throws XMLStreamException {
    XMLInputFactory factory = XMLInputFactory.newFactory();
    factory.setProperty(XMLInputFactory.SUPPORT_DTD, false);
    factory.setProperty(XMLInputFactory.IS_COALESCING, false);
    XMLStreamReader xml = factory.createXMLStreamReader(log);
    List<Compilation> found = new ArrayList<>();
    Set<String> replaced = new HashSet<>();
    Map<String, Integer> codeBytes = new HashMap<>();
    TaskReader task = null;
    while (xml.hasNext()) {
      int event = xml.next();
      if (event == XMLStreamReader.START_ELEMENT) {
        String name = xml.getLocalName();
        if (name.equals("make_not_entrant")) {
          replaced.add(xml.getAttributeValue(null, "compile_id"));
        } else if (name.equals("nmethod")) {
          String from = xml.getAttributeValue(null, "insts_offset");
          String to = xml.getAttributeValue(null, "stub_offset");
          if (from != null && to != null) {
            codeBytes.put(
                xml.getAttributeValue(null, "compile_id"),
                Integer.parseInt(to) - Integer.parseInt(from));
          }
        } else if (name.equals("task")) {
          task = TaskReader.of(xml);
        } else if (task != null) {
          task.start(name, xml);
        }
      } else if (event == XMLStreamReader.END_ELEMENT && task != null) {
        if (xml.getLocalName().equals("task")) {
          task.result().ifPresent(found::add);
          task = null;
        } else {
          task.end(xml.getLocalName());
        }
      }
    }
    List<Compilation> marked = new ArrayList<>();
    for (Compilation c : found) {
      marked.add(
          new Compilation(
              c.stamp(), c.id(), c.osr(), c.method(), c.blockCalls(), c.refused(),
              replaced.contains(c.id()), codeBytes.getOrDefault(c.id(), -1)));
    }
    marked.sort(Comparator.comparingDouble(Compilation::stamp));
    return marked;
  }

  /** Follows one {@code <task>}: the inlining tree C2 logs while it parses. */
  private static final class TaskReader {
    private final double stamp;
    private final String id;
    private final boolean osr;
    private final String method;
    private final boolean wanted;
    private final Map<String, String> klasses = new HashMap<>();
    private final Map<String, String> methods = new HashMap<>();
    private final Deque<String> parsing = new ArrayDeque<>();
    private final List<String> refused = new ArrayList<>();
    private String lastCall;
    private int blockCalls;

    private TaskReader(double stamp, String id, boolean osr, String method, boolean wanted) {
      this.stamp = stamp;
      this.id = id;
      this.osr = osr;
      this.method = method;
      this.wanted = wanted;
    }

    static TaskReader of(XMLStreamReader xml) {
      String level = xml.getAttributeValue(null, "level");
      String signature = xml.getAttributeValue(null, "method");
      String[] parts = signature == null ? new String[0] : signature.split(" ");
      String method = parts.length >= 2 ? parts[0] + "::" + parts[1] : String.valueOf(signature);
      boolean c2 = level == null || level.equals("4");
      boolean wanted =
          c2
              && (method.contains("_jmhStub")
                  || method.startsWith("dev.prime.liberty.")
                  || method.startsWith("dev.prime.radiant."));
      String stamp = xml.getAttributeValue(null, "stamp");
      return new TaskReader(
          stamp == null ? 0 : Double.parseDouble(stamp),
          xml.getAttributeValue(null, "compile_id"),
          "osr".equals(xml.getAttributeValue(null, "compile_kind")),
          method.substring(method.lastIndexOf('.') + 1),
          wanted);
    }

    void start(String name, XMLStreamReader xml) {
      switch (name) {
        case "klass" -> klasses.put(attr(xml, "id"), attr(xml, "name"));
        case "method" ->
            methods.put(
                attr(xml, "id"),
                klasses.getOrDefault(attr(xml, "holder"), "?") + "::" + attr(xml, "name"));
        case "parse" -> parsing.push(methods.getOrDefault(attr(xml, "method"), "?"));
        case "call" -> lastCall = methods.getOrDefault(attr(xml, "method"), "?");
        case "inline_success" -> {
          String caller = parsing.isEmpty() ? "" : parsing.peek();
          if (lastCall != null && lastCall.startsWith(BLOCKS) && !caller.startsWith(BLOCKS)) {
            blockCalls++;
          }
        }
        case "inline_fail" -> {
          if (lastCall != null && lastCall.startsWith("dev.prime.")) {
            refused.add(lastCall.substring(lastCall.lastIndexOf('.') + 1)
                + " (" + attr(xml, "reason") + ")");
          }
        }
        default -> {}
      }
    }

    void end(String name) {
      if (name.equals("parse") && !parsing.isEmpty()) {
        parsing.pop();
      }
    }

    Optional<Compilation> result() {
      return wanted
          ? Optional.of(
              new Compilation(
                  stamp, id, osr, method, blockCalls, List.copyOf(refused), false, -1))
          : Optional.empty();
    }

    private static String attr(XMLStreamReader xml, String name) {
      String value = xml.getAttributeValue(null, name);
      return value == null ? "" : value;
    }
  }
}
