// Apache Jena (Debian libapache-jena-java 4.5) as the reference for smartfactory's rule engine:
// loads ontology and data, runs GenericRuleReasoner in FORWARD_RETE mode with the given Jena
// rule files and writes the deductions graph (the triples the rules added) as N-Triples.
//
//   java -cp CLASSPATH JenaReason --data F.ttl [--data F.nt ...] --rules F.rules [...]
//        [--out F.nt] [--stats] [--updates N --update-property IRI]
//
// --updates N: after the closure, N live-value changes on the InfModel (remove the value of
// the property on one subject, add value + 1), each timed; --stats reports their median and
// 99th percentile, as bench/bench_knowledge does for ours.
//
// tests/integration/kb_jena_test.py compares the output with `smartfactory kb reason`;
// bench/bench_knowledge runs it with --stats for the time figures. Node formatting is our own
// (not RIOT's writer) so that generalized triples (literal subjects) print too, and blank node
// labels (makeSkolem produces base64 labels) are renamed to _:b<n>.
import java.io.*;
import java.nio.charset.StandardCharsets;
import java.util.*;

import org.apache.jena.graph.Graph;
import org.apache.jena.graph.Node;
import org.apache.jena.graph.Triple;
import org.apache.jena.rdf.model.InfModel;
import org.apache.jena.rdf.model.Model;
import org.apache.jena.rdf.model.ModelFactory;
import org.apache.jena.rdf.model.RDFNode;
import org.apache.jena.reasoner.rulesys.GenericRuleReasoner;
import org.apache.jena.reasoner.rulesys.Rule;
import org.apache.jena.riot.RDFDataMgr;

public class JenaReason {
  private static final String XSD_STRING = "http://www.w3.org/2001/XMLSchema#string";
  private final Map<String, String> blankIds = new HashMap<>();

  public static void main(String[] args) throws Exception {
    List<String> data = new ArrayList<>();
    List<String> rules = new ArrayList<>();
    String out = null;
    boolean stats = false;
    int updates = 0;
    String updateProperty = null;
    for (int i = 0; i < args.length; i++) {
      switch (args[i]) {
        case "--data": data.add(args[++i]); break;
        case "--rules": rules.add(args[++i]); break;
        case "--out": out = args[++i]; break;
        case "--stats": stats = true; break;
        case "--updates": updates = Integer.parseInt(args[++i]); break;
        case "--update-property": updateProperty = args[++i]; break;
        default: throw new IllegalArgumentException("unknown argument " + args[i]);
      }
    }
    new JenaReason().run(data, rules, out, stats, updates, updateProperty);
  }

  private void run(List<String> data, List<String> ruleFiles, String out, boolean stats, int updates,
                   String updateProperty) throws IOException {
    long t0 = System.nanoTime();
    Model model = ModelFactory.createDefaultModel();
    for (String f : data) RDFDataMgr.read(model, f);
    List<Rule> rules = new ArrayList<>();
    for (String f : ruleFiles) {
      try (BufferedReader r = new BufferedReader(new InputStreamReader(new FileInputStream(f), StandardCharsets.UTF_8))) {
        rules.addAll(Rule.parseRules(Rule.rulesParserFromReader(r)));
      }
    }
    long t1 = System.nanoTime();
    GenericRuleReasoner reasoner = new GenericRuleReasoner(rules);
    reasoner.setMode(GenericRuleReasoner.FORWARD_RETE);
    InfModel inf = ModelFactory.createInfModel(reasoner, model);
    inf.prepare();
    long t2 = System.nanoTime();
    Graph deductions = inf.getDeductionsModel().getGraph();
    long count = 0;
    try (Writer w = new BufferedWriter(out == null ? new OutputStreamWriter(System.out, StandardCharsets.UTF_8)
                                                   : new OutputStreamWriter(new FileOutputStream(out), StandardCharsets.UTF_8))) {
      for (Iterator<Triple> it = deductions.find(Node.ANY, Node.ANY, Node.ANY); it.hasNext();) {
        Triple t = it.next();
        w.write(format(t.getSubject()) + " " + format(t.getPredicate()) + " " + format(t.getObject()) + " .\n");
        count++;
      }
    }
    double[] latencies = updates > 0 ? update(inf, updates, updateProperty) : new double[0];
    if (stats) {
      System.gc();
      java.lang.ref.Reference.reachabilityFence(inf);
      Runtime rt = Runtime.getRuntime();
      double heapMb = (rt.totalMemory() - rt.freeMemory()) / 1048576.0;
      System.err.printf(Locale.ROOT,
                        "{\"load_ms\": %.3f, \"reason_ms\": %.3f, \"input_triples\": %d, \"inferred\": %d, "
                            + "\"heap_after_gc_mb\": %.1f, \"update_median_ms\": %.4f, \"update_p99_ms\": %.4f}%n",
                        (t1 - t0) / 1e6, (t2 - t1) / 1e6, model.size(), count, heapMb, percentile(latencies, 0.5),
                        percentile(latencies, 0.99));
    }
  }

  // Live values through the InfModel: the RETE engine retracts and derives incrementally.
  private static double[] update(InfModel inf, int n, String property) {
    org.apache.jena.rdf.model.Property p = inf.createProperty(property);
    List<org.apache.jena.rdf.model.Statement> targets = inf.getRawModel().listStatements(null, p, (RDFNode) null).toList();
    double[] ms = new double[Math.min(n, targets.size())];
    for (int i = 0; i < ms.length; i++) {
      org.apache.jena.rdf.model.Statement s = targets.get(i);
      double next = s.getObject().asLiteral().getDouble() + 1.0;
      long t0 = System.nanoTime();
      inf.remove(s);
      inf.add(s.getSubject(), p, inf.createTypedLiteral(next));
      inf.prepare();
      ms[i] = (System.nanoTime() - t0) / 1e6;
    }
    return ms;
  }

  private static double percentile(double[] v, double q) {
    if (v.length == 0) return 0;
    double[] s = v.clone();
    Arrays.sort(s);
    return s[Math.min(s.length - 1, (int) Math.floor(q * s.length))];
  }

  // N-Triples term syntax (RDF 1.1 N-Triples §2.3–2.5); xsd:string is the implicit datatype.
  private String format(Node n) {
    if (n.isURI()) return "<" + escape(n.getURI()) + ">";
    if (n.isBlank()) return "_:" + blankIds.computeIfAbsent(n.getBlankNodeLabel(), k -> "b" + blankIds.size());
    if (n.isLiteral()) {
      String s = "\"" + escape(n.getLiteralLexicalForm()) + "\"";
      String lang = n.getLiteralLanguage();
      if (lang != null && !lang.isEmpty()) return s + "@" + lang;
      String dt = n.getLiteralDatatypeURI();
      return (dt == null || dt.equals(XSD_STRING)) ? s : s + "^^<" + escape(dt) + ">";
    }
    return "\"" + escape(n.toString()) + "\"";
  }

  private static String escape(String s) {
    StringBuilder b = new StringBuilder(s.length());
    for (int i = 0; i < s.length(); i++) {
      char c = s.charAt(i);
      switch (c) {
        case '\\': b.append("\\\\"); break;
        case '"': b.append("\\\""); break;
        case '\n': b.append("\\n"); break;
        case '\r': b.append("\\r"); break;
        case '\t': b.append("\\t"); break;
        default:
          if (c < 0x20) b.append(String.format("\\u%04X", (int) c));
          else b.append(c);
      }
    }
    return b.toString();
  }
}
