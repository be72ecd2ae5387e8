// Fuzzes the Jena rule parser and, for rules it accepts, the engine: a rule set from arbitrary
// text runs over a small candy-factory graph with a low derivation limit. Parsing must accept
// or reject with a positioned error; running must end (fixpoint or the limit) without crashing,
// and an incremental update afterwards must keep working.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/reasoner.hpp"

namespace {

void check(bool ok) {
  if (!ok) {
    __builtin_trap();
  }
}

constexpr std::string_view kData = R"(
@prefix sf: <http://smartfactory.example/ontology/candy#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
sf:ScaraRobot rdfs:subClassOf sf:Robot . sf:Robot rdfs:subClassOf sf:Machine .
sf:r1 a sf:ScaraRobot ; sf:temperature "74.5"^^xsd:double ; sf:maxTemperature 70 ; sf:state "fault: jam" ;
  sf:hasComponent sf:c1 ; sf:canPerform sf:PickAndPlace ; rdfs:label "robot one"@en .
sf:c1 sf:hasComponent sf:s1 . sf:op1 sf:assignedTo sf:r1 ; sf:requiresCapability sf:BoxLoading .
sf:o1 sf:orderCode "ORD-000042" ; sf:dueAt "2024-05-01T11:00:00Z"^^xsd:dateTime ; sf:quantity 3 .
)";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sf::knowledge;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Dictionary dict;
  auto rules = parse_rules(text, "fuzz.rules", dict);
  if (!rules) {
    check(rules.error().message.rfind("fuzz.rules:", 0) == 0);
    return 0;
  }
  auto doc = read_rdf_string(dict, kData, Syntax::turtle, "data.ttl");
  check(doc.ok());
  ReasonerOptions options;
  options.max_derived = 2000;
  options.print = [](const std::string&) {};
  Reasoner reasoner(dict, std::move(*rules), options);
  reasoner.add_data(doc->triples);
  if (!reasoner.run().ok()) {
    return 0;
  }
  const TermId r1 = dict.iri("http://smartfactory.example/ontology/candy#r1");
  const TermId temperature = dict.iri("http://smartfactory.example/ontology/candy#temperature");
  (void)reasoner.set_value(r1, temperature, dict.literal("20.0", "http://www.w3.org/2001/XMLSchema#double"));
  for (const Violation& v : reasoner.violations()) {
    check(v.because.rule != nullptr);
  }
  return 0;
}
