#include "sf/examples/factory_data.hpp"

#include <fstream>

#include "test_util.hpp"

namespace sf::knowledge {
namespace {

using examples::FactoryDataOptions;
using examples::generate_factory_data;

std::set<std::string> all_lines(const Dictionary& d, const std::vector<Triple>& t) {
  return testing::lines(d, t);
}

TEST(FactoryData, SameSeedSameDataAtTheAskedScale) {
  Dictionary d;
  FactoryDataOptions o;
  o.target_triples = 5000;
  const auto a = generate_factory_data(d, o);
  const auto b = generate_factory_data(d, o);
  EXPECT_GE(a.size(), 5000U);
  EXPECT_LT(a.size(), 5000U + 3000U);  // one line more at most
  EXPECT_EQ(all_lines(d, a), all_lines(d, b));
  o.seed = 2;
  EXPECT_NE(all_lines(d, generate_factory_data(d, o)), all_lines(d, a));
}

// The generated data exercises the candy-factory requirements: with the shipped rules, every
// kind of violation the generator injects is found.
TEST(FactoryData, ViolatesEachRequirementSomewhere) {
  Dictionary d;
  FactoryDataOptions o;
  o.target_triples = 40000;
  o.violation_rate = 0.2;
  const std::string root = SF_SOURCE_DIR;
  RuleSet rules;
  for (const char* f : {"/rules/rdfs.rules", "/rules/owl2rl.rules", "/rules/candy-factory.rules"}) {
    auto set = read_rules_file(root + f, d);
    ASSERT_TRUE(set.ok()) << set.error().message;
    std::move(set->rules.begin(), set->rules.end(), std::back_inserter(rules.rules));
  }
  auto onto = read_rdf_file(d, root + "/ontology/candy-factory.ttl");
  ASSERT_TRUE(onto.ok()) << onto.error().message;
  auto catalog = read_rdf_file(d, root + "/ontology/prototype-line.ttl");  // candy and box types
  ASSERT_TRUE(catalog.ok()) << catalog.error().message;
  Reasoner r(d, std::move(rules), ReasonerOptions{10'000'000, [](const std::string&) {}});
  r.add_data(onto->triples);
  r.add_data(catalog->triples);
  r.add_data(generate_factory_data(d, o));
  ASSERT_TRUE(r.run().ok());
  std::set<std::string> kinds;
  for (const Violation& v : r.violations()) {
    kinds.insert(v.because.rule->label());
  }
  for (const char* rule :
       {"temperatureHigh", "temperatureLow", "overspeed", "axisTravel", "fault", "contentMismatch",
        "overCapacity", "overfilled", "late", "cannotPerform", "alarmRaised", "cax-dw", "prp-fp-literal"}) {
    EXPECT_TRUE(kinds.count(rule)) << rule;
  }
}

}  // namespace
}  // namespace sf::knowledge
