package dev.prime.bench.report;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.ByteArrayInputStream;
import java.nio.charset.StandardCharsets;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * Reading a compilation log: block calls counted once each (not again for a block's bridge
 * method), refusals with C2's reason, only C2 compilations of JMH loops and Prime classes, code
 * sizes and replaced code from the log's {@code nmethod} and {@code make_not_entrant} lines.
 */
class InliningReportTest {
  private static final String LOG =
      """
      <?xml version='1.0' encoding='UTF-8'?>
      <hotspot_log version='160 1' process='1' time_ms='1'>
      <nmethod compile_id='646' compiler='c2' level='4' insts_offset='656' stub_offset='3568'/>
      <nmethod compile_id='680' compiler='c2' level='4' insts_offset='400' stub_offset='1040'/>
      <make_not_entrant thread='1' compile_id='650' compile_kind='osr'/>
      <compilation_log thread='2'>
      <task compile_id='680' method='x.SyncChainBenchmark_liberty_jmhTest liberty_avgt_jmhStub (I)V' bytes='63' stamp='9.370'>
      <klass id='1' name='dev.prime.liberty.RunSequences$Seq2' flags='24'/>
      <klass id='2' name='dev.prime.Block' flags='1537'/>
      <method id='3' holder='2' name='process' bytes='0'/>
      <method id='4' holder='1' name='process' bytes='22'/>
      <parse method='9'>
      <call method='3' virtual='1' inline='1' receiver='1'/>
      <call method='4' inline='1'/>
      <inline_fail reason='already compiled into a big method'/>
      </parse>
      </task>
      <task compile_id='646' method='dev.prime.liberty.RunSequences$Seq2 process (Ljava/lang/Object;)Ljava/lang/Object;' bytes='22' stamp='8.218'>
      <klass id='1' name='dev.prime.liberty.RunSequences$Seq2' flags='24'/>
      <klass id='2' name='dev.prime.Block' flags='1537'/>
      <klass id='5' name='dev.prime.liberty.Runs$Run16' flags='24'/>
      <klass id='6' name='dev.prime.bench.PacketBlocks$Add' flags='25'/>
      <method id='3' holder='2' name='process' bytes='0'/>
      <method id='4' holder='1' name='process' bytes='22'/>
      <method id='7' holder='5' name='process' bytes='234'/>
      <method id='8' holder='6' name='process' bytes='9'/>
      <method id='9' holder='6' name='process' bytes='15'/>
      <parse method='4'>
      <call method='3' virtual='1' inline='1' receiver='5'/>
      <call method='7' inline='1'/>
      <inline_success reason='inline (hot)'/>
      <parse method='7'>
      <call method='3' virtual='1' inline='1' receiver='6'/>
      <call method='8' inline='1'/>
      <inline_success reason='inline (hot)'/>
      <parse method='8'>
      <call method='9' inline='1'/>
      <inline_success reason='inline (hot)'/>
      <parse method='9'>
      </parse>
      </parse>
      <call method='3' virtual='1' inline='1' receiver='6'/>
      <call method='8' inline='1'/>
      <inline_success reason='inline (hot)'/>
      <parse method='8'>
      <call method='9' inline='1'/>
      <inline_success reason='inline (hot)'/>
      <parse method='9'>
      </parse>
      </parse>
      </parse>
      </parse>
      </task>
      <task compile_id='643' method='dev.prime.liberty.RunSequences$Seq2 process (Ljava/lang/Object;)Ljava/lang/Object;' bytes='22' level='3' stamp='7.973'>
      </task>
      <task compile_id='650' compile_kind='osr' method='x.SyncChainBenchmark_liberty_jmhTest liberty_avgt_jmhStub (I)V' bytes='63' level='4' stamp='8.475'>
      </task>
      <task compile_id='700' method='java.lang.String hashCode ()I' bytes='60' stamp='9.5'>
      </task>
      </compilation_log>
      </hotspot_log>
      """;

  private static List<InliningReport.Compilation> read() throws Exception {
    return InliningReport.read(new ByteArrayInputStream(LOG.getBytes(StandardCharsets.UTF_8)));
  }

  @Test
  void countsEachBlockCallOnceAndListsRefusalsInStartOrder() throws Exception {
    List<InliningReport.Compilation> compilations = read();
    assertEquals(List.of("646", "650", "680"),
        compilations.stream().map(InliningReport.Compilation::id).toList());

    InliningReport.Compilation root = compilations.get(0);
    assertEquals("RunSequences$Seq2::process", root.method());
    assertEquals(2, root.blockCalls()); // two Add calls; their bridges' inner calls not counted
    assertTrue(root.refused().isEmpty());
    assertEquals(3568 - 656, root.codeBytes());
    assertFalse(root.osr());

    InliningReport.Compilation stub = compilations.get(2);
    assertEquals(0, stub.blockCalls());
    assertEquals(
        List.of("RunSequences$Seq2::process (already compiled into a big method)"),
        stub.refused());
    assertTrue(stub.describe().contains("640 B of code"), stub.describe());
  }

  @Test
  void marksOnStackReplacementAndReplacedCode() throws Exception {
    InliningReport.Compilation osr = read().get(1);
    assertTrue(osr.osr());
    assertTrue(osr.replaced());
    assertEquals(-1, osr.codeBytes());
    assertFalse(read().get(2).replaced());
  }
}
