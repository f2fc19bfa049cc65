package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.Token;
import dev.prime.Tuple2;
import dev.prime.Tuple3;
import dev.prime.Tuple4;
import dev.prime.Tuple5;
import dev.prime.mcap.internal.JsonSchemaGenerator;
import java.io.IOException;
import java.math.BigDecimal;
import java.math.BigInteger;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.OptionalInt;
import java.util.Set;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** Every supported value type written to an MCAP file and read back equal, with its schema. */
class RoundTripTest {
  @TempDir Path dir;

  enum Gear { PARK, DRIVE, REVERSE }

  record Pose(double x, double y, double theta) {}

  record Everything(
      boolean flag, byte b, short s, int i, long l, float f, double d, char c,
      Boolean boxedFlag, Integer boxedInt, Long boxedLong, Double boxedDouble, Character boxedChar,
      String text, BigInteger big, BigDecimal decimal, Gear gear,
      List<Pose> path, Set<String> tags, Map<String, Double> gains, Map<Gear, Integer> byGear,
      Map<Integer, String> byId, int[] counts, String[] names, Pose[] poses,
      Optional<Pose> target, Optional<String> note, OptionalInt limit, Token token) {}

  record Tree(String label, List<Tree> children) {}

  record Wrapper(Optional<Tree> tree) {}

  /** Writes values of one type and returns what the reader decodes, with the channel's schema. */
  private <T> List<T> roundTrip(ValueType<T> type, List<T> values) throws IOException {
    Path file = dir.resolve("values.mcap");
    try (McapWriter writer = McapWriter.open(file)) {
      McapChannel<T> channel = writer.channel("values", type);
      long t = 1_000;
      for (T value : values) {
        assertTrue(channel.write(t, t + 1, t / 1000, value));
        t += 1_000;
      }
    }
    try (McapReader reader = McapReader.open(file)) {
      ChannelInfo channel = reader.channel("values").orElseThrow();
      assertEquals("json", channel.messageEncoding());
      SchemaInfo schema = channel.schema().orElseThrow();
      assertEquals("jsonschema", schema.encoding());
      assertEquals(type.name(), schema.name());
      assertEquals(type.jsonSchema(), schema.text());
      assertEquals(values.size(), reader.messageCount("values"));
      List<TypedMessage<T>> read = reader.messages("values", type).collect(Collectors.toList());
      for (int k = 0; k < read.size(); k++) {
        assertEquals(1_000L * (k + 1), read.get(k).logTime());
        assertEquals(1_000L * (k + 1) + 1, read.get(k).publishTime());
        assertEquals(k + 1, read.get(k).sequence());
      }
      return read.stream().map(TypedMessage::value).collect(Collectors.toList());
    }
  }

  private <T> void assertRoundTrip(ValueType<T> type, List<T> values) throws IOException {
    assertEquals(values, roundTrip(type, values));
  }

  @Test
  void primitivesBoxesAndStrings() throws IOException {
    assertRoundTrip(ValueType.of(Integer.class), List.of(0, -1, Integer.MAX_VALUE, Integer.MIN_VALUE));
    assertRoundTrip(ValueType.of(Long.class), List.of(Long.MIN_VALUE, 0L, Long.MAX_VALUE));
    assertRoundTrip(ValueType.of(Double.class), List.of(0.0, -1.5, Double.MAX_VALUE, Double.MIN_VALUE));
    assertRoundTrip(ValueType.of(Float.class), List.of(1.25f, -0.1f));
    assertRoundTrip(ValueType.of(Short.class), List.of((short) -3, Short.MAX_VALUE));
    assertRoundTrip(ValueType.of(Byte.class), List.of((byte) -128, (byte) 127));
    assertRoundTrip(ValueType.of(Boolean.class), List.of(true, false));
    assertRoundTrip(ValueType.of(Character.class), List.of('a', 'é', '"'));
    assertRoundTrip(ValueType.of(String.class), List.of("", "plain", "quote \" and \\ and \n and ü and 🤖"));
    assertRoundTrip(ValueType.of(BigInteger.class), List.of(new BigInteger("123456789012345678901234567890")));
    assertRoundTrip(ValueType.of(BigDecimal.class), List.of(new BigDecimal("3.14159265358979323846")));
  }

  @Test
  void nonFiniteDoublesComeBack() throws IOException {
    assertRoundTrip(ValueType.of(Double.class), List.of(Double.NaN, Double.POSITIVE_INFINITY, Double.NEGATIVE_INFINITY));
  }

  @Test
  void enumsAndTokens() throws IOException {
    assertRoundTrip(ValueType.of(Gear.class), List.of(Gear.DRIVE, Gear.PARK, Gear.REVERSE));
    assertRoundTrip(ValueType.of(Token.class), List.of(Token.INSTANCE, Token.INSTANCE));
    assertTrue(ValueType.of(Gear.class).jsonSchema().contains("\"enum\" : [ \"PARK\", \"DRIVE\", \"REVERSE\" ]"));
  }

  @Test
  void recordsWithEveryKindOfComponent() throws IOException {
    Map<String, Double> gains = new LinkedHashMap<>();
    gains.put("kp", 1.5);
    gains.put("ki", 0.01);
    Everything full = new Everything(
        true, (byte) 7, (short) -300, 42, 1L << 40, 0.5f, Math.PI, 'z',
        Boolean.FALSE, 17, -9L, 2.5, 'q',
        "hello", BigInteger.TEN.pow(30), new BigDecimal("0.1"), Gear.REVERSE,
        List.of(new Pose(0, 0, 0), new Pose(1, 2, 0.5)), Set.of("a", "b"), gains,
        Map.of(Gear.DRIVE, 3), Map.of(7, "seven", -1, "minus one"),
        new int[] {1, 2, 3}, new String[] {"x", "y"}, new Pose[] {new Pose(3, 4, 5)},
        Optional.of(new Pose(9, 9, 9)), Optional.empty(), OptionalInt.of(5), Token.INSTANCE);
    Everything sparse = new Everything(
        false, (byte) 0, (short) 0, 0, 0, 0, 0, 'a',
        null, null, null, null, null,
        null, null, null, null,
        List.of(), Set.of(), Map.of(), Map.of(), Map.of(),
        new int[0], new String[0], new Pose[0],
        Optional.empty(), Optional.empty(), OptionalInt.empty(), null);
    List<Everything> back = roundTrip(ValueType.of(Everything.class), List.of(full, sparse));
    assertEverythingEquals(full, back.get(0));
    assertEverythingEquals(sparse, back.get(1));
  }

  private static void assertEverythingEquals(Everything expected, Everything actual) {
    assertArrayEquals(expected.counts(), actual.counts());
    assertArrayEquals(expected.names(), actual.names());
    assertArrayEquals(expected.poses(), actual.poses());
    // with the arrays equal, the rest compares component by component
    Everything withoutArrays = new Everything(
        actual.flag(), actual.b(), actual.s(), actual.i(), actual.l(), actual.f(), actual.d(), actual.c(),
        actual.boxedFlag(), actual.boxedInt(), actual.boxedLong(), actual.boxedDouble(), actual.boxedChar(),
        actual.text(), actual.big(), actual.decimal(), actual.gear(), actual.path(), actual.tags(),
        actual.gains(), actual.byGear(), actual.byId(), expected.counts(), expected.names(), expected.poses(),
        actual.target(), actual.note(), actual.limit(), actual.token());
    assertEquals(expected, withoutArrays);
  }

  @Test
  void collectionsMapsArraysAndOptionalsAtTheTop() throws IOException {
    assertRoundTrip(new ValueType<List<Pose>>() {}, List.of(List.of(new Pose(1, 2, 3)), List.of()));
    assertRoundTrip(new ValueType<Set<Gear>>() {}, List.of(Set.of(Gear.PARK, Gear.DRIVE)));
    assertRoundTrip(new ValueType<Map<String, List<Integer>>>() {}, List.of(Map.of("a", List.of(1, 2)), Map.of()));
    assertRoundTrip(new ValueType<Optional<Pose>>() {}, List.of(Optional.of(new Pose(1, 1, 1)), Optional.empty()));
    List<byte[]> blobs = roundTrip(ValueType.of(byte[].class), List.of(new byte[] {0, 1, -1, 127}, new byte[0]));
    assertArrayEquals(new byte[] {0, 1, -1, 127}, blobs.get(0));
    assertArrayEquals(new byte[0], blobs.get(1));
    List<double[]> vectors = roundTrip(ValueType.of(double[].class), List.of(new double[] {1.5, -2}));
    assertArrayEquals(new double[] {1.5, -2}, vectors.get(0));
  }

  @Test
  void primeTuplesWithTheirTypeArguments() throws IOException {
    assertRoundTrip(new ValueType<Tuple2<Double, String>>() {}, List.of(new Tuple2<>(1.5, "a")));
    assertRoundTrip(new ValueType<Tuple3<Integer, Pose, Gear>>() {},
        List.of(new Tuple3<>(1, new Pose(1, 2, 3), Gear.DRIVE)));
    assertRoundTrip(new ValueType<Tuple4<Long, List<String>, Token, Boolean>>() {},
        List.of(new Tuple4<>(4L, List.of("x"), Token.INSTANCE, true)));
    assertRoundTrip(new ValueType<Tuple5<Integer, Integer, Integer, Integer, Tuple2<String, Double>>>() {},
        List.of(new Tuple5<>(1, 2, 3, 4, new Tuple2<>("five", 5.0))));
    String schema = new ValueType<Tuple2<Double, Gear>>() {}.jsonSchema();
    assertTrue(schema.contains("\"first\" : {\n      \"type\" : \"number\""), schema);
    assertTrue(schema.contains("\"second\" : {\n      \"type\" : \"string\",\n      \"enum\""), schema);
  }

  @Test
  void recursiveRecordsAndAnyJson() throws IOException {
    Tree tree = new Tree("root", List.of(new Tree("leaf", List.of())));
    assertRoundTrip(ValueType.of(Tree.class), List.of(tree));
    // Foxglove follows no $ref: a recursive record is inlined to a bounded depth, then any JSON.
    String treeSchema = ValueType.of(Tree.class).jsonSchema();
    assertFalse(treeSchema.contains("$ref"), treeSchema);
    assertEquals(
        JsonSchemaGenerator.RECURSION_DEPTH,
        treeSchema.split("\"label\"", -1).length - 1, treeSchema);
    assertTrue(treeSchema.contains("nested deeper than"), treeSchema);
    Tree deep = new Tree("0", List.of());
    for (int i = 1; i <= JsonSchemaGenerator.RECURSION_DEPTH + 3; i++) {
      deep = new Tree(Integer.toString(i), List.of(deep));
    }
    assertRoundTrip(ValueType.of(Tree.class), List.of(deep)); // written and read in full
    assertRoundTrip(ValueType.of(Wrapper.class), List.of(new Wrapper(Optional.of(tree)), new Wrapper(Optional.empty())));
    assertFalse(ValueType.of(Wrapper.class).jsonSchema().contains("$ref"));
    JsonNode any = new ObjectMapper().readTree("{\"a\":[1,{\"b\":null}],\"c\":\"d\"}");
    assertRoundTrip(ValueType.of(JsonNode.class), List.of(any));
  }

  @Test
  void everyMessageIsAJsonObjectAValueNotARecordWrappedAsValue() throws IOException {
    Path file = dir.resolve("wrapped.mcap");
    try (McapWriter writer = McapWriter.open(file)) {
      writer.channel("int", Integer.class).write(1, 1, 0, 42);
      writer.channel("gear", Gear.class).write(1, 1, 0, Gear.DRIVE);
      writer.channel("token", Token.class).write(1, 1, 0, Token.INSTANCE);
      writer.channel("text", String.class).write(1, 1, 0, "hi");
      writer.channel("list", new ValueType<List<Double>>() {}).write(1, 1, 0, List.of(1.0, 2.0));
      writer.channel("map", new ValueType<Map<String, Integer>>() {}).write(1, 1, 0, Map.of("a", 1));
      writer.channel("optional", new ValueType<Optional<String>>() {}).write(1, 1, 0, Optional.empty());
    }
    try (McapReader reader = McapReader.open(file)) {
      List<String> texts = reader.messages().map(McapMessage::text).collect(Collectors.toList());
      assertEquals(
          List.of("{\"value\":42}", "{\"value\":\"DRIVE\"}", "{\"value\":\"INSTANCE\"}",
              "{\"value\":\"hi\"}", "{\"value\":[1.0,2.0]}", "{\"value\":{\"a\":1}}",
              "{\"value\":null}"),
          texts);
      assertEquals(7, reader.schemas().size());
      for (SchemaInfo info : reader.schemas()) {
        JsonNode schema = new ObjectMapper().readTree(info.data());
        assertEquals("object", schema.get("type").asText(), info.name());
        assertEquals(Set.of("value"), fieldNames(schema.get("properties")), info.name());
      }
      assertEquals(42, reader.messages("int", Integer.class).findFirst().orElseThrow().value());
      assertEquals(Token.INSTANCE, reader.messages("token", Token.class).findFirst().orElseThrow().value());
      assertEquals(Map.of("a", 1),
          reader.messages("map", new ValueType<Map<String, Integer>>() {}).findFirst().orElseThrow().value());
      assertEquals(Optional.empty(),
          reader.messages("optional", new ValueType<Optional<String>>() {}).findFirst().orElseThrow().value());
    }
    IllegalArgumentException bare =
        assertThrows(IllegalArgumentException.class,
            () -> ValueType.of(Integer.class).fromJson("42".getBytes(java.nio.charset.StandardCharsets.UTF_8)));
    assertTrue(bare.getMessage().contains("{\"value\": ...}"), bare.getMessage());
  }

  private static Set<String> fieldNames(JsonNode node) {
    Set<String> names = new java.util.HashSet<>();
    node.fieldNames().forEachRemaining(names::add);
    return names;
  }

  @Test
  void theJsonHasExactlyTheRecordComponents() throws IOException {
    Path file = dir.resolve("json.mcap");
    try (McapWriter writer = McapWriter.open(file)) {
      writer.channel("pose", Pose.class).write(1, 1, 0, new Pose(1, 2, 3));
      writer.channel("tuple", new ValueType<Tuple2<Integer, Optional<String>>>() {})
          .write(1, 1, 0, new Tuple2<>(7, Optional.empty()));
    }
    try (McapReader reader = McapReader.open(file)) {
      List<McapMessage> messages = reader.messages().collect(Collectors.toList());
      assertEquals("{\"x\":1.0,\"y\":2.0,\"theta\":3.0}", messages.get(0).text());
      assertEquals("{\"first\":7,\"second\":null}", messages.get(1).text());
      assertEquals(2.0, messages.get(0).json().get("y").asDouble());
    }
  }

  static final class NotARecord {
    int value;
  }

  record HoldsObject(String name, List<Object> things) {}

  record KeyedByPose(Map<Pose, String> names) {}

  interface Shape {}

  @Test
  void unsupportedTypesAreRefusedWithThePathToThem() {
    IllegalArgumentException plain = assertThrows(IllegalArgumentException.class, () -> ValueType.of(NotARecord.class));
    assertTrue(plain.getMessage().contains("NotARecord (at value) is not a value type"), plain.getMessage());
    assertTrue(plain.getMessage().contains("record its fields in a record"), plain.getMessage());
    IllegalArgumentException object = assertThrows(IllegalArgumentException.class, () -> ValueType.of(HoldsObject.class));
    assertTrue(object.getMessage().contains("java.lang.Object (at value.things[])"), object.getMessage());
    IllegalArgumentException key = assertThrows(IllegalArgumentException.class, () -> ValueType.of(KeyedByPose.class));
    assertTrue(key.getMessage().contains("map keys at value.names"), key.getMessage());
    assertThrows(IllegalArgumentException.class, () -> ValueType.of(Shape.class));
    IllegalArgumentException generic = assertThrows(IllegalArgumentException.class, () -> ValueType.of(Tuple2.class));
    assertTrue(generic.getMessage().contains("new ValueType<Tuple2<...>>() {}"), generic.getMessage());
    IllegalArgumentException arrayList = assertThrows(IllegalArgumentException.class,
        () -> new ValueType<ArrayList<String>>() {});
    assertTrue(arrayList.getMessage().contains("declare collections as List"), arrayList.getMessage());
  }

  /** A {@link Pose} without its {@code theta}. */
  record Planar(double x, double y) {}

  /** A primitive component missing from a message's JSON is an error when read, not a zero. */
  @Test
  void aPrimitiveComponentMissingFromTheJsonIsAnErrorNotAZero() throws IOException {
    Path file = dir.resolve("missing.mcap");
    try (McapWriter writer = McapWriter.open(file)) {
      writer.channel("pose", Planar.class).write(1, 1, 0, new Planar(1, 2));
    }
    try (McapReader reader = McapReader.open(file)) {
      IllegalArgumentException e = assertThrows(IllegalArgumentException.class,
          () -> reader.messages("pose", Pose.class).collect(Collectors.toList()),
          "a Pose read from JSON without theta");
      assertTrue(e.getMessage().contains("is not a " + ValueType.of(Pose.class).name()), e.getMessage());
    }
  }

  @Test
  void decodingIntoTheWrongTypeSaysWhich() throws IOException {
    Path file = dir.resolve("wrong.mcap");
    try (McapWriter writer = McapWriter.open(file)) {
      writer.channel("pose", Pose.class).write(1, 1, 0, new Pose(1, 2, 3));
    }
    try (McapReader reader = McapReader.open(file)) {
      IllegalArgumentException e = assertThrows(IllegalArgumentException.class,
          () -> reader.messages("pose", Gear.class).collect(Collectors.toList()));
      assertTrue(e.getMessage().contains("on 'pose' (schema " + ValueType.of(Pose.class).name() + ")"), e.getMessage());
      assertTrue(e.getMessage().contains("is not a " + ValueType.of(Gear.class).name()), e.getMessage());
      IllegalArgumentException topic = assertThrows(IllegalArgumentException.class, () -> reader.messages("nope"));
      assertTrue(topic.getMessage().contains("no channel has topic 'nope'") && topic.getMessage().contains("[pose]"),
          topic.getMessage());
    }
  }
}
