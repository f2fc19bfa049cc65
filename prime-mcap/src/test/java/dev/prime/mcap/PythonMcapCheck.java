package dev.prime.mcap;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import java.io.IOException;
import java.io.InputStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.StandardCopyOption;
import java.util.List;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Assumptions;

/**
 * The independent MCAP reader for tests: the Python {@code mcap} package (with {@code
 * jsonschema}), pinned, installed into the module's {@code target/python-mcap} (once per build
 * directory), running {@code check_mcap.py} on a file. {@link #installOrSkip()} aborts the calling
 * test (skipped, with the reason) where python3 is missing or pip cannot reach PyPI. The system
 * property {@code prime.mcap.python} names another interpreter. Shipped in prime-mcap's test-jar,
 * so other modules' tests (the robot example's) check their files the same way.
 *
 * <p>{@link #check(Path, Path)} returns the script's JSON: {@code channels} (per topic: {@code
 * statistics_count}, {@code read_count}, {@code first}, {@code schema_name}, {@code
 * message_encoding}, {@code schema_encoding}, {@code rejects_probe}), {@code message_count},
 * {@code chunk_count}, {@code chunk_indexes}, {@code schema_errors}, {@code log_time_sorted},
 * {@code summary_crc_ok}, {@code summary_offset_groups}, {@code streamed_chunks}, {@code
 * stream_records}, {@code library}.
 */
public final class PythonMcapCheck {
  /** The pinned {@code mcap} package. */
  public static final String MCAP = "mcap==1.6.0";
  /** The pinned {@code jsonschema} package. */
  public static final String JSONSCHEMA = "jsonschema==4.26.0";

  private static final String PYTHON = System.getProperty("prime.mcap.python", "python3");

  private final Path packages;

  private PythonMcapCheck(Path packages) {
    this.packages = packages;
  }

  /**
   * Installs the packages into {@code target/python-mcap} of the module under test (Maven's
   * {@code basedir}), or aborts the calling test saying why it cannot.
   *
   * @return the check, ready to run
   * @throws IOException if the target directory cannot be written
   * @throws InterruptedException if interrupted while pip runs
   */
  public static PythonMcapCheck installOrSkip() throws IOException, InterruptedException {
    Path target = Path.of(System.getProperty("basedir", ".")).resolve("target").resolve("python-mcap");
    Path marker = target.resolve(".installed-" + MCAP + "-" + JSONSCHEMA);
    Process version = start(List.of(PYTHON, "--version"), null);
    if (version == null || !version.waitFor(30, TimeUnit.SECONDS) || version.exitValue() != 0) {
      Assumptions.abort(PYTHON + " is not on the PATH: the independent check with the Python mcap package is skipped");
    }
    if (Files.exists(marker)) {
      return new PythonMcapCheck(target);
    }
    Files.createDirectories(target);
    Path log = target.resolveSibling("python-mcap-pip.log");
    Process pip = start(List.of(PYTHON, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
        "--no-input", "--retries", "1", "--timeout", "30", "--upgrade", "--target", target.toString(),
        MCAP, JSONSCHEMA), log);
    if (pip == null) {
      Assumptions.abort(PYTHON + " -m pip could not be started: the independent check is skipped");
    }
    boolean finished = pip.waitFor(240, TimeUnit.SECONDS);
    if (!finished) {
      pip.destroyForcibly();
    }
    if (!finished || pip.exitValue() != 0) {
      String output = Files.exists(log) ? Files.readString(log, StandardCharsets.UTF_8) : "";
      Assumptions.abort("pip could not install " + MCAP + " and " + JSONSCHEMA + " (no pip, or PyPI"
          + " unreachable), so the independent check is skipped; pip said:\n" + output);
    }
    Files.createFile(marker);
    return new PythonMcapCheck(target);
  }

  /**
   * Runs {@code check_mcap.py} on a file.
   *
   * @param file the MCAP file
   * @param workDir a directory for the script and its output
   * @return the script's findings
   * @throws AssertionError if the script fails (the Python reader refused the file) or runs for
   *     more than 90 s
   * @throws IOException if the script cannot be written or run
   * @throws InterruptedException if interrupted while it runs
   */
  public JsonNode check(Path file, Path workDir) throws IOException, InterruptedException {
    Path script = workDir.resolve("check_mcap.py");
    try (InputStream in = PythonMcapCheck.class.getResourceAsStream("check_mcap.py")) {
      Files.copy(in, script, StandardCopyOption.REPLACE_EXISTING);
    }
    ProcessBuilder builder = new ProcessBuilder(PYTHON, script.toString(), file.toString());
    builder.environment().put("PYTHONPATH", packages.toString());
    Path output = workDir.resolve("check.out");
    Path errors = workDir.resolve("check.err");
    builder.redirectOutput(output.toFile()).redirectError(errors.toFile());
    Process process = builder.start();
    if (!process.waitFor(90, TimeUnit.SECONDS)) {
      process.destroyForcibly();
      throw new AssertionError("the Python check did not finish in 90 s");
    }
    if (process.exitValue() != 0) {
      throw new AssertionError("the Python mcap reader failed on " + file + ":\n"
          + Files.readString(errors, StandardCharsets.UTF_8));
    }
    return new ObjectMapper().readTree(Files.readString(output, StandardCharsets.UTF_8));
  }

  private static Process start(List<String> command, Path log) throws IOException {
    ProcessBuilder builder = new ProcessBuilder(command).redirectErrorStream(true);
    if (log != null) {
      builder.redirectOutput(log.toFile());
    } else {
      builder.redirectOutput(ProcessBuilder.Redirect.DISCARD);
    }
    try {
      return builder.start();
    } catch (IOException e) {
      return null;
    }
  }
}
