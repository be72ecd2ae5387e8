#include "test_util.hpp"

namespace sf::knowledge {
namespace {

TEST(RuleParser, ReadsJenaSyntax) {
  Dictionary d;
  auto set = parse_rules(
      "# a comment\n"
      "// another\n"
      "@prefix ex: <http://ex/>.\n"
      "[r1: (?a ex:p ?b), (?b rdf:type ex:C) -> (?a ex:q ?b)]\n"
      "[ (?a ex:t ?t) greaterThan(?t, 80.5) sum(?t, 1, ?u) -> (?a ex:hot 'yes') (?a ex:n \"2\"^^xsd:int)\n"
      "  print(?a, 'is hot') ]\n"
      "(?a ex:z ?b) -> (?b ex:z ?a) .\n",
      "r.rules", d);
  ASSERT_TRUE(set.ok()) << set.error().message;
  ASSERT_EQ(set->rules.size(), 3U);
  const Rule& r1 = set->rules[0];
  EXPECT_EQ(r1.name, "r1");
  EXPECT_EQ(r1.body.size(), 2U);
  EXPECT_EQ(r1.variables, (std::vector<std::string>{"?a", "?b"}));
  const auto& p = std::get<TriplePattern>(r1.body[1]);
  EXPECT_EQ(d.term(p.p.term).text, vocab::kRdfType);  // rdf: is known without @prefix
  const Rule& r2 = set->rules[1];
  EXPECT_TRUE(r2.name.empty());
  EXPECT_EQ(r2.label(), "rule at r.rules:5");
  const auto& gt = std::get<BuiltinCall>(r2.body[1]);
  EXPECT_EQ(gt.op, Builtin::greater_than);
  EXPECT_EQ(d.term(gt.args[1].term).datatype, vocab::kXsdFloat);  // Jena: 80.5 is an xsd:float
  const auto& sum = std::get<BuiltinCall>(r2.body[2]);
  EXPECT_EQ(d.term(sum.args[1].term).datatype, vocab::kXsdInt);
  EXPECT_EQ(std::get<BuiltinCall>(r2.head[2]).op, Builtin::print);
  EXPECT_TRUE(r2.monotonic());
  EXPECT_EQ(set->rules[2].head.size(), 1U);
}

TEST(RuleParser, NonMonotonicBuiltinsMarkTheRule) {
  Dictionary d;
  auto set = parse_rules(
      "@prefix ex: <http://ex/>.\n"
      "[a: (?x ex:p ?y) noValue(?x, ex:q) -> (?x ex:r ?y)]\n"
      "[b: (?x ex:p ?y) (?y ex:p ?z) -> remove(1)]\n",
      "nm.rules", d);
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_FALSE(set->rules[0].monotonic());
  EXPECT_FALSE(set->rules[1].monotonic());
}

struct BadRule {
  const char* text;
  const char* where;  // expected "file:line:column" prefix
  const char* says;   // part of the message
};

class RuleErrors : public ::testing::TestWithParam<BadRule> {};

TEST_P(RuleErrors, NameFileLineAndColumn) {
  Dictionary d;
  auto set = parse_rules(GetParam().text, "bad.rules", d);
  ASSERT_FALSE(set.ok()) << GetParam().text;
  EXPECT_EQ(set.error().code, Errc::malformed);
  EXPECT_EQ(set.error().message.rfind(GetParam().where, 0), 0U) << set.error().message;
  EXPECT_NE(set.error().message.find(GetParam().says), std::string::npos) << set.error().message;
}

INSTANTIATE_TEST_SUITE_P(
    Jena, RuleErrors,
    ::testing::Values(
        BadRule{"[r: (?a foo:p ?b) -> (?a ex:q ?b)]", "bad.rules:1:9:", "unknown prefix 'foo:'"},
        BadRule{"\n[r: (?a rdf:type 'open -> (?a rdf:type ?b)]", "bad.rules:2:18:", "unterminated literal"},
        BadRule{"[r: (?a rdf:type) -> (?a rdf:type ?b)]", "bad.rules:1:5:", "3 terms"},
        BadRule{"[r: (?a rdf:type ?b) frobnicate(?a) -> (?a rdf:type ?b)]",
                "bad.rules:1:22:", "unknown builtin"},
        BadRule{"[r: (?a rdf:type ?b) lessThan(?a) -> (?a rdf:type ?b)]",
                "bad.rules:1:22:", "takes 2 arguments"},
        BadRule{"[r: (?a rdf:type ?b) -> sum(?a, 1, ?c)]",
                "bad.rules:1:25:", "cannot be used in a rule head"},
        BadRule{"[r: (?a rdf:type ?b) lessThan(?b, 1) -> remove(1)]", "bad.rules:1:41:", "remove()"},
        BadRule{"[r: (?a rdf:type ?b) -> (?a rdf:type ?b)", "bad.rules:1:1:", "not closed with ']'"},
        BadRule{"[r: (?a rdf:type ?b) <- (?a rdf:type ?b)]", "bad.rules:1:22:", "backward rules"},
        BadRule{"[r: (?a type ?b) -> (?a rdf:type ?b)]", "bad.rules:1:9:", "is not a term"},
        BadRule{"@include <rdfs>.\n", "bad.rules:1:1:", "unsupported directive"},
        BadRule{"[r: (?a rdf:type ?b)\n   (?a rdf:type *) -> (?a rdf:type ?b)]",
                "bad.rules:2:17:", "wildcard"}));

}  // namespace
}  // namespace sf::knowledge
