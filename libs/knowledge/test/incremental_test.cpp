// Incremental maintenance must give exactly the closure a fresh run over the changed data gives.
#include <random>

#include "test_util.hpp"

namespace sf::knowledge {
namespace {

using testing::closure;
using testing::inferred;

struct Incremental : ::testing::Test {
  Dictionary d;
  TermId ex(std::string_view local) { return d.iri("http://ex/" + std::string(local)); }
  TermId dbl(double v) { return d.literal(java_double_string(v), vocab::kXsdDouble); }
};

constexpr std::string_view kLine =
    "[sc: (?x rdf:type ?c) (?c rdfs:subClassOf ?d) -> (?x rdf:type ?d)]\n"
    "[part: (?a ex:hasComponent ?b) (?b ex:hasComponent ?c) -> (?a ex:hasComponent ?c)]\n"
    "[hot: (?m ex:temperature ?t) (?m rdf:type ?c) (?c ex:maxTemperature ?x) greaterThan(?t, ?x)\n"
    "      strConcat('temperature ', ?t, ' above ', ?x, ?msg) -> (?m rb:violation ?msg)]\n"
    "[idle: (?m rdf:type ex:Machine) noValue(?m, ex:assignedTo) -> (?m ex:status ex:Idle)]\n";

constexpr std::string_view kData =
    "ex:Scara rdfs:subClassOf ex:Robot . ex:Robot rdfs:subClassOf ex:Machine .\n"
    "ex:Robot ex:maxTemperature \"70.0\"^^xsd:double .\n"
    "ex:r1 a ex:Scara ; ex:temperature \"40.0\"^^xsd:double ; ex:hasComponent ex:ctrl .\n"
    "ex:ctrl ex:hasComponent ex:slave . ex:slave ex:hasComponent ex:axis1 .\n";

TEST_F(Incremental, LiveValueReplacesItsViolation) {
  Reasoner r(d, testing::rules(d, kLine));
  r.add_data(testing::turtle(d, kData));
  ASSERT_TRUE(r.run().ok());
  EXPECT_TRUE(r.violations().empty());
  auto up = r.set_value(ex("r1"), ex("temperature"), dbl(85.0));
  ASSERT_TRUE(up.ok()) << up.error().message;
  auto v = r.violations();
  ASSERT_EQ(v.size(), 1U);
  EXPECT_EQ(d.term(v[0].triple.o).text, "temperature 85.0 above 70.0");
  ASSERT_TRUE(r.set_value(ex("r1"), ex("temperature"), dbl(90.0)).ok());
  v = r.violations();
  ASSERT_EQ(v.size(), 1U);
  EXPECT_EQ(d.term(v[0].triple.o).text, "temperature 90.0 above 70.0");  // the 85.0 one is retracted
  auto cool = r.set_value(ex("r1"), ex("temperature"), dbl(30.0));
  ASSERT_TRUE(cool.ok());
  EXPECT_TRUE(r.violations().empty());
  EXPECT_EQ(cool->retracted, 1U);
}

TEST_F(Incremental, NoValueConclusionsFollowTheTestedPredicate) {
  Reasoner r(d, testing::rules(d, kLine));
  r.add_data(testing::turtle(d, kData));
  ASSERT_TRUE(r.run().ok());
  const Triple idle{ex("r1"), ex("status"), ex("Idle")};
  EXPECT_NE(r.store().find(idle), kNoTriple);
  const Triple assigned{ex("r1"), ex("assignedTo"), ex("op7")};
  ASSERT_TRUE(r.update(Changes{{assigned}, {}}).ok());
  EXPECT_EQ(r.store().find(idle), kNoTriple);
  ASSERT_TRUE(r.update(Changes{{}, {assigned}}).ok());
  EXPECT_NE(r.store().find(idle), kNoTriple);
}

TEST_F(Incremental, AlternativeSupportKeepsADerivedTriple) {
  Reasoner r(d, testing::rules(d, kLine));
  r.add_data(testing::turtle(d, kData));
  r.add_data(testing::turtle(d, "ex:r1 a ex:Robot ."));  // Machine follows from Scara and from Robot
  ASSERT_TRUE(r.run().ok());
  const Triple machine{ex("r1"), d.iri(vocab::kRdfType), ex("Machine")};
  ASSERT_TRUE(r.update(Changes{{}, {Triple{ex("r1"), d.iri(vocab::kRdfType), ex("Scara")}}}).ok());
  EXPECT_NE(r.store().find(machine), kNoTriple);
  ASSERT_TRUE(r.update(Changes{{}, {Triple{ex("r1"), d.iri(vocab::kRdfType), ex("Robot")}}}).ok());
  EXPECT_EQ(r.store().find(machine), kNoTriple);
}

TEST_F(Incremental, RetractingDataThatIsAlsoDerivedKeepsIt) {
  Reasoner r(d, testing::rules(d, kLine));
  r.add_data(testing::turtle(d, kData));
  r.add_data(testing::turtle(d, "ex:r1 a ex:Machine ."));
  ASSERT_TRUE(r.run().ok());
  const Triple machine{ex("r1"), d.iri(vocab::kRdfType), ex("Machine")};
  ASSERT_TRUE(r.update(Changes{{}, {machine}}).ok());
  const TripleId id = r.store().find(machine);
  ASSERT_NE(id, kNoTriple);  // still follows from Scara ⊑ Robot ⊑ Machine
  EXPECT_TRUE(r.explain(id).has_value());
}

// Random updates of a component tree and class memberships: after each, the incrementally
// maintained closure equals the closure a new reasoner computes from the same data.
TEST_F(Incremental, RandomUpdatesMatchRecomputation) {
  std::mt19937 rng(GTEST_FLAG_GET(random_seed) == 0 ? 7U
                                                    : static_cast<unsigned>(GTEST_FLAG_GET(random_seed)));
  const auto rule_text = std::string(kLine);
  Reasoner live(d, testing::rules(d, rule_text));
  std::set<std::tuple<TermId, TermId, TermId>> data;
  for (const Triple& t : testing::turtle(d, kData)) {
    data.insert({t.s, t.p, t.o});
  }
  std::vector<Triple> initial;
  for (const auto& [s, p, o] : data) {
    initial.push_back({s, p, o});
  }
  live.add_data(initial);
  ASSERT_TRUE(live.run().ok());
  const std::vector<TermId> nodes = {ex("r1"), ex("ctrl"), ex("slave"), ex("axis1"), ex("n5"), ex("n6")};
  const std::vector<TermId> classes = {ex("Scara"), ex("Robot"), ex("Machine")};
  for (int round = 0; round < 150; ++round) {
    Changes c;
    for (int k = 0; k < 3; ++k) {
      Triple t;
      switch (rng() % 4) {
        case 0:
          t = {nodes[rng() % nodes.size()], ex("hasComponent"), nodes[rng() % nodes.size()]};
          break;
        case 1:
          t = {nodes[rng() % nodes.size()], d.iri(vocab::kRdfType), classes[rng() % classes.size()]};
          break;
        case 2:
          t = {nodes[rng() % nodes.size()], ex("assignedTo"), ex("op1")};
          break;
        default:
          t = {nodes[rng() % nodes.size()], ex("temperature"), dbl(static_cast<double>(rng() % 100))};
          break;
      }
      if (std::find(c.add.begin(), c.add.end(), t) != c.add.end() ||
          std::find(c.remove.begin(), c.remove.end(), t) != c.remove.end()) {
        continue;  // one change per triple and round
      }
      const bool present = data.count({t.s, t.p, t.o}) != 0;
      (present ? c.remove : c.add).push_back(t);
      if (present) {
        data.erase({t.s, t.p, t.o});
      } else {
        data.insert({t.s, t.p, t.o});
      }
    }
    ASSERT_TRUE(live.update(c).ok());
    std::vector<Triple> now;
    for (const auto& [s, p, o] : data) {
      now.push_back({s, p, o});
    }
    Reasoner fresh(d, testing::rules(d, rule_text));
    fresh.add_data(now);
    ASSERT_TRUE(fresh.run().ok());
    const auto a = closure(live);
    const auto b = closure(fresh);
    std::string diff;
    for (const auto& l : a) {
      diff += b.count(l) ? "" : "only incremental: " + l + "\n";
    }
    for (const auto& l : b) {
      diff += a.count(l) ? "" : "only recomputed: " + l + "\n";
    }
    ASSERT_TRUE(diff.empty()) << "round " << round << "\n" << diff;
  }
}

}  // namespace
}  // namespace sf::knowledge
