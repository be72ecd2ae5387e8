// `smartfactory kb reason|to-nodeset|generate`: the knowledge layer of the paper (§VI) from the
// command line — reason over an ontology, data and Jena rules; turn the ontology into an OPC UA
// NodeSet2; generate candy-factory data. Everything here parses options and prints; the
// knowledge module does the work.
#include <chrono>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/examples/factory_data.hpp"
#include "sf/knowledge/nodeset.hpp"
#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/reasoner.hpp"

namespace sf::app {
namespace {

namespace kb = sf::knowledge;
using nlohmann::json;

int kb_fail(std::string_view command, const Error& e) {
  std::cerr << "kb " << command << ": " << e.message << "\n";
  return kExitFailure;
}

// Reads every RDF file into one list; the first error stops (nothing is used).
Result<std::vector<kb::Triple>> read_all(kb::Dictionary& dict, const std::vector<std::string>& files,
                                         std::map<std::string, std::string>* prefixes = nullptr) {
  std::vector<kb::Triple> all;
  for (const std::string& f : files) {
    auto doc = kb::read_rdf_file(dict, f);
    if (!doc) {
      return doc.error();
    }
    all.insert(all.end(), doc->triples.begin(), doc->triples.end());
    if (prefixes != nullptr) {
      prefixes->insert(doc->prefixes.begin(), doc->prefixes.end());
    }
  }
  return all;
}

// --- reason -------------------------------------------------------------------------------

struct ReasonOptions {
  std::vector<std::string> ontology;
  std::vector<std::string> data;
  std::vector<std::string> rules;
  std::string output;
  std::size_t max_derived = kb::ReasonerOptions{}.max_derived;
  bool explain = false;
  bool json = false;
};

std::vector<std::string> triple_lines(const kb::Reasoner& r, const std::vector<kb::TripleId>& ids) {
  std::vector<std::string> out;
  out.reserve(ids.size());
  for (kb::TripleId id : ids) {
    out.push_back(kb::format_triple(r.dictionary(), r.store().at(id)));
  }
  return out;
}

json derivation_json(const kb::Reasoner& r, const kb::Derivation& d) {
  if (d.rule == nullptr) {
    return json{{"rule", nullptr}, {"at", nullptr}, {"matched", json::array()}};
  }
  return json{
      {"rule", d.rule->label()}, {"at", d.rule->pos.describe()}, {"matched", triple_lines(r, d.premises)}};
}

std::string derivation_text(const kb::Reasoner& r, const kb::Derivation& d) {
  if (d.rule == nullptr) {
    return "no derivation recorded";
  }
  std::string line = fmt::format("rule {} ({})", d.rule->label(), d.rule->pos.describe());
  for (const std::string& t : triple_lines(r, d.premises)) {
    line += "\n#     " + t;
  }
  return line;
}

void print_json(const kb::Reasoner& r, const ReasonOptions& o, double ms) {
  json out;
  const auto inferred = r.inferred();
  out["inferred"] = triple_lines(r, inferred);
  if (o.explain) {
    json derivations = json::array();
    for (kb::TripleId id : inferred) {
      derivations.push_back(derivation_json(r, r.explain(id).value_or(kb::Derivation{})));
    }
    out["derivations"] = derivations;
  }
  json violations = json::array();
  for (const kb::Violation& v : r.violations()) {
    json item{{"subject", kb::format_term(r.dictionary(), v.triple.s)},
              {"message", std::string(r.dictionary().term(v.triple.o).text)},
              {"triple", kb::format_triple(r.dictionary(), v.triple)}};
    item.update(derivation_json(r, v.because));
    violations.push_back(item);
  }
  out["violations"] = violations;
  const auto st = r.stats();
  out["stats"] = {{"data", st.asserted}, {"inferred", st.inferred}, {"firings", st.firings}, {"ms", ms}};
  std::cout << out.dump(2) << "\n";
}

Status print_text(const kb::Reasoner& r, const ReasonOptions& o) {
  std::ofstream file;
  std::ostream* out = &std::cout;
  if (!o.output.empty()) {
    file.open(o.output);
    if (!file) {
      return make_error(Errc::io, fmt::format("{}: cannot create", o.output));
    }
    out = &file;
  }
  const auto inferred = r.inferred();
  if (o.explain) {
    for (kb::TripleId id : inferred) {
      *out << "# " << derivation_text(r, r.explain(id).value_or(kb::Derivation{})) << "\n"
           << kb::format_triple(r.dictionary(), r.store().at(id)) << "\n";
    }
  } else {
    std::vector<kb::Triple> triples;
    triples.reserve(inferred.size());
    for (kb::TripleId id : inferred) {
      triples.push_back(r.store().at(id));
    }
    SF_TRY(kb::write_rdf(*out, r.dictionary(), triples,
                         o.output.empty() ? kb::Syntax::ntriples : kb::syntax_for_path(o.output)));
  }
  // Violations as N-Triples comments, so that the output stays a valid N-Triples document.
  const auto violations = r.violations();
  std::cout << "# " << violations.size() << " violation(s)\n";
  for (const kb::Violation& v : violations) {
    std::cout << "# violation: " << kb::format_term(r.dictionary(), v.triple.s) << ": "
              << r.dictionary().term(v.triple.o).text << "\n#   by " << derivation_text(r, v.because) << "\n";
  }
  return {};
}

int run_reason(const ReasonOptions& o) {
  kb::Dictionary dict;
  std::vector<std::string> rdf = o.ontology;
  rdf.insert(rdf.end(), o.data.begin(), o.data.end());
  auto triples = read_all(dict, rdf);
  if (!triples) {
    return kb_fail("reason", triples.error());
  }
  kb::RuleSet rules;
  for (const std::string& f : o.rules) {
    auto set = kb::read_rules_file(f, dict);
    if (!set) {
      return kb_fail("reason", set.error());
    }
    std::move(set->rules.begin(), set->rules.end(), std::back_inserter(rules.rules));
  }
  kb::ReasonerOptions ro;
  ro.max_derived = o.max_derived;
  ro.print = [](const std::string& line) { std::cerr << "print: " << line << "\n"; };
  kb::Reasoner reasoner(dict, std::move(rules), ro);
  reasoner.add_data(*triples);
  const auto t0 = std::chrono::steady_clock::now();
  auto result = reasoner.run();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!result) {
    return kb_fail("reason", result.error());
  }
  if (o.json) {
    print_json(reasoner, o, ms);
  } else if (auto st = print_text(reasoner, o); !st) {
    return kb_fail("reason", st.error());
  }
  const auto st = reasoner.stats();
  std::cerr << fmt::format(
      "kb reason: {} data triples, {} inferred, {} violation(s), {} rule firings in {:.1f} ms\n", st.asserted,
      st.inferred, reasoner.violations().size(), st.firings, ms);
  return kExitOk;
}

// --- to-nodeset ---------------------------------------------------------------------------

struct NodesetCliOptions {
  std::vector<std::string> inputs;
  std::string output;
  std::string namespace_uri;
};

int run_to_nodeset(const NodesetCliOptions& o) {
  kb::Dictionary dict;
  auto triples = read_all(dict, o.inputs);
  if (!triples) {
    return kb_fail("to-nodeset", triples.error());
  }
  auto model = kb::extract_ontology(dict, *triples);
  if (!model) {
    return kb_fail("to-nodeset", model.error());
  }
  std::ofstream out(o.output);
  if (!out) {
    return kb_fail("to-nodeset", make_error(Errc::io, fmt::format("{}: cannot create", o.output)));
  }
  kb::NodesetOptions opts;
  opts.namespace_uri = o.namespace_uri;
  if (auto st = kb::write_nodeset(out, dict, *model, opts); !st) {
    return kb_fail("to-nodeset", st.error());
  }
  std::cerr << fmt::format("kb to-nodeset: {} object types, {} properties, {} objects → {}\n",
                           model->classes.size(), model->properties.size(), model->individuals.size(),
                           o.output);
  return kExitOk;
}

// --- generate -----------------------------------------------------------------------------

struct GenerateOptions {
  examples::FactoryDataOptions data;
  std::string output;
};

int run_generate(const GenerateOptions& o) {
  kb::Dictionary dict;
  const auto triples = examples::generate_factory_data(dict, o.data);
  std::ofstream out(o.output);
  if (!out) {
    return kb_fail("generate", make_error(Errc::io, fmt::format("{}: cannot create", o.output)));
  }
  const std::map<std::string, std::string> prefixes{{"sf", "http://smartfactory.example/ontology/candy#"},
                                                    {"f", std::string(examples::kFactoryDataNamespace)}};
  if (auto st = kb::write_rdf(out, dict, triples, kb::syntax_for_path(o.output), prefixes); !st) {
    return kb_fail("generate", st.error());
  }
  std::cerr << fmt::format("kb generate: {} triples → {}\n", triples.size(), o.output);
  return kExitOk;
}

}  // namespace

void register_kb(CLI::App& app, CommandResult& result) {
  auto* kb_cmd = app.add_subcommand("kb",
                                    "Knowledge layer: reason over the ontology, data and rules; export the "
                                    "ontology as an OPC UA NodeSet2 (paper section VI)");
  kb_cmd->require_subcommand(1);

  auto reason = std::make_shared<ReasonOptions>();
  auto* r = kb_cmd->add_subcommand(
      "reason",
      "Run Jena rules forward over ontology and data; print the inferred triples (N-Triples) and violations");
  r->add_option("--ontology", reason->ontology, "Ontology file (Turtle, or N-Triples if .nt); repeatable")
      ->check(CLI::ExistingFile);
  r->add_option("--data", reason->data, "Data file (Turtle, or N-Triples if .nt); repeatable")
      ->check(CLI::ExistingFile);
  r->add_option("--rules", reason->rules, "Rule file in Jena syntax; repeatable")
      ->required()
      ->check(CLI::ExistingFile);
  r->add_flag("--explain", reason->explain, "With every inferred triple, the rule and the matched triples");
  r->add_flag("--json", reason->json, "Print inferred triples, violations and statistics as JSON");
  r->add_option("--max-derived", reason->max_derived,
                "Stop with an error after deriving this many triples (rules that never terminate)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  r->add_option("-o,--output", reason->output,
                "Write the inferred triples to this file (.nt N-Triples, else Turtle) instead of stdout "
                "(text output; violations stay on stdout)");
  r->callback([reason, &result] { result.exit_code = run_reason(*reason); });

  auto nodeset = std::make_shared<NodesetCliOptions>();
  auto* n = kb_cmd->add_subcommand(
      "to-nodeset", "Turn an ontology (and individuals) into an OPC UA NodeSet2 XML information model");
  n->add_option("inputs", nodeset->inputs, "Ontology and data files (Turtle or N-Triples)")
      ->required()
      ->check(CLI::ExistingFile);
  n->add_option("-o,--output", nodeset->output, "NodeSet2 XML file to write")->required();
  n->add_option("--namespace", nodeset->namespace_uri,
                "Namespace URI of the model (default: the owl:Ontology IRI)");
  n->callback([nodeset, &result] { result.exit_code = run_to_nodeset(*nodeset); });

  auto gen = std::make_shared<GenerateOptions>();
  auto* g = kb_cmd->add_subcommand("generate",
                                   "Generate candy-factory data (production lines, orders, live values)");
  g->add_option("--triples", gen->data.target_triples, "Generate at least this many triples")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  g->add_option("--seed", gen->data.seed, "Random seed: the same seed gives the same data")
      ->capture_default_str();
  g->add_option("--orders-per-line", gen->data.orders_per_line, "Orders per production line")
      ->capture_default_str();
  g->add_option("--violation-rate", gen->data.violation_rate,
                "Share of live values and assignments that break a requirement")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  g->add_option("-o,--output", gen->output, "File to write (.nt N-Triples, else Turtle)")->required();
  g->callback([gen, &result] { result.exit_code = run_generate(*gen); });
}

}  // namespace sf::app
