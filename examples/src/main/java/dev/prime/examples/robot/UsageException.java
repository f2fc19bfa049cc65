package dev.prime.examples.robot;

/** The command line is wrong; the message says what and {@link RobotOptions#USAGE} how. */
public final class UsageException extends IllegalArgumentException {
  private static final long serialVersionUID = 1L;

  /**
   * @param message what is wrong with the command line
   */
  public UsageException(String message) {
    super(message);
  }
}
