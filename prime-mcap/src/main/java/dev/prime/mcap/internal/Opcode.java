package dev.prime.mcap.internal;

/** The MCAP record opcodes this module writes or reads (mcap.dev specification, version 0). */
public final class Opcode {
  private Opcode() {}

  /** Header. */
  public static final int HEADER = 0x01;
  /** Footer. */
  public static final int FOOTER = 0x02;
  /** Schema. */
  public static final int SCHEMA = 0x03;
  /** Channel. */
  public static final int CHANNEL = 0x04;
  /** Message. */
  public static final int MESSAGE = 0x05;
  /** Chunk. */
  public static final int CHUNK = 0x06;
  /** Message Index. */
  public static final int MESSAGE_INDEX = 0x07;
  /** Chunk Index. */
  public static final int CHUNK_INDEX = 0x08;
  /** Attachment. */
  public static final int ATTACHMENT = 0x09;
  /** Attachment Index. */
  public static final int ATTACHMENT_INDEX = 0x0A;
  /** Statistics. */
  public static final int STATISTICS = 0x0B;
  /** Metadata. */
  public static final int METADATA = 0x0C;
  /** Metadata Index. */
  public static final int METADATA_INDEX = 0x0D;
  /** Summary Offset. */
  public static final int SUMMARY_OFFSET = 0x0E;
  /** Data End. */
  public static final int DATA_END = 0x0F;

  /** The 8 bytes every MCAP file (major version 0) starts and ends with. */
  public static final byte[] MAGIC = {(byte) 0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};

  /**
   * @param opcode an opcode
   * @return the spec's name for it, for error messages
   */
  public static String name(int opcode) {
    switch (opcode) {
      case HEADER: return "Header";
      case FOOTER: return "Footer";
      case SCHEMA: return "Schema";
      case CHANNEL: return "Channel";
      case MESSAGE: return "Message";
      case CHUNK: return "Chunk";
      case MESSAGE_INDEX: return "MessageIndex";
      case CHUNK_INDEX: return "ChunkIndex";
      case ATTACHMENT: return "Attachment";
      case ATTACHMENT_INDEX: return "AttachmentIndex";
      case STATISTICS: return "Statistics";
      case METADATA: return "Metadata";
      case METADATA_INDEX: return "MetadataIndex";
      case SUMMARY_OFFSET: return "SummaryOffset";
      case DATA_END: return "DataEnd";
      default: return String.format("opcode 0x%02X", opcode);
    }
  }
}
