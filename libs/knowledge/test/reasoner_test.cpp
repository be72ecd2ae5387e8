#include "test_util.hpp"

namespace sf::knowledge {
namespace {

using testing::inferred;

struct Reasoning : ::testing::Test {
  Dictionary d;
  std::vector<std::string> printed;

  std::unique_ptr<Reasoner> reason(std::string_view data, std::string_view rule_text,
                                   std::size_t limit = 1000000) {
    ReasonerOptions opts;
    opts.max_derived = limit;
    opts.print = [this](const std::string& line) { printed.push_back(line); };
    auto r = std::make_unique<Reasoner>(d, testing::rules(d, rule_text), opts);
    const auto data_triples = testing::turtle(d, data);
    r->add_data(data_triples);
    auto st = r->run();
    EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().message);
    return r;
  }
};

constexpr std::string_view kSubclass =
    "[sc: (?x rdf:type ?c) (?c rdfs:subClassOf ?d) -> (?x rdf:type ?d)]\n"
    "[tr: (?c rdfs:subClassOf ?d) (?d rdfs:subClassOf ?e) -> (?c rdfs:subClassOf ?e)]\n";

TEST_F(Reasoning, SubclassClosure) {
  auto r = reason(
      "ex:Scara rdfs:subClassOf ex:Robot . ex:Robot rdfs:subClassOf ex:Machine .\n"
      "ex:r1 a ex:Scara .",
      kSubclass);
  const std::set<std::string> want{
      "ex:r1 <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> ex:Robot .",
      "ex:r1 <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> ex:Machine .",
      "ex:Scara <http://www.w3.org/2000/01/rdf-schema#subClassOf> ex:Machine .",
  };
  EXPECT_EQ(inferred(*r), want);
}

TEST_F(Reasoning, DerivedTriplesEqualByValueToDataAreNotAdded) {
  auto r = reason("ex:a ex:p \"1\"^^xsd:int .",
                  "[r: (ex:a ex:p ?x) -> (ex:a ex:p '1.0'^^xsd:decimal) (ex:a ex:q '1.0'^^xsd:decimal)]");
  EXPECT_EQ(inferred(*r),
            (std::set<std::string>{"ex:a ex:q \"1.0\"^^<http://www.w3.org/2001/XMLSchema#decimal> ."}));
}

TEST_F(Reasoning, PatternConstantsAndJoinsMatchByValue) {
  auto r = reason("ex:m ex:limit 20 . ex:m ex:temp \"20.0\"^^xsd:decimal . ex:n ex:temp \"20\"^^xsd:int .",
                  "[j: (?m ex:limit ?l) (?m ex:temp ?l) -> (?m ex:atLimit ex:yes)]\n"
                  "[c: (?m ex:temp 20) -> (?m ex:twenty ex:yes)]");
  EXPECT_EQ(inferred(*r), (std::set<std::string>{"ex:m ex:atLimit ex:yes .", "ex:m ex:twenty ex:yes .",
                                                 "ex:n ex:twenty ex:yes ."}));
}

TEST_F(Reasoning, ComparisonAndArithmeticBuiltins) {
  auto r = reason(
      "ex:m ex:temp \"85.5\"^^xsd:double ; ex:max 80 ; ex:min 10 ; ex:count 7 ; ex:day "
      "\"2024-05-02T00:00:00Z\"^^xsd:dateTime .",
      "[hot: (?m ex:temp ?t) (?m ex:max ?x) greaterThan(?t, ?x) difference(?t, ?x, ?over)\n"
      "      -> (?m ex:over ?over)]\n"
      "[ok: (?m ex:temp ?t) (?m ex:max ?x) le(?t, ?x) -> (?m ex:ok ex:yes)]\n"
      "[half: (?m ex:count ?n) quotient(?n, 2, ?h) product(?n, 3, ?p) min(?n, 5, ?lo) max(?n, 5, ?hi)\n"
      "      -> (?m ex:half ?h) (?m ex:triple ?p) (?m ex:lo ?lo) (?m ex:hi ?hi)]\n"
      "[eq: (?m ex:count ?n) equal(?n, '7.0'^^xsd:decimal) notEqual(?n, 8) -> (?m ex:seven ex:yes)]\n"
      "[late: (?m ex:day ?d) greaterThan(?d, '2024-05-01T23:00:00-02:00'^^xsd:dateTime) -> (?m ex:late "
      "ex:yes)]\n"
      "[bad: (?m ex:count ?n) lessThan(?n, 'seven') -> (?m ex:never ex:yes)]");
  const std::string xsd = "<http://www.w3.org/2001/XMLSchema#";
  EXPECT_EQ(inferred(*r), (std::set<std::string>{
                              "ex:m ex:over \"5.5\"^^" + xsd + "double> .",
                              "ex:m ex:half \"3\"^^" + xsd + "int> .",
                              "ex:m ex:triple \"21\"^^" + xsd + "int> .",
                              "ex:m ex:lo \"5\"^^" + xsd + "int> .",
                              "ex:m ex:hi \"7\"^^" + xsd + "integer> .",
                              "ex:m ex:seven ex:yes .",
                          }));
}

TEST_F(Reasoning, StringBuiltinsAndSkolemNodes) {
  auto r = reason("ex:o1 ex:code \"ORD-0042\" . ex:o2 ex:code \"bogus\" .",
                  "[num: (?o ex:code ?c) regex(?c, 'ORD-([0-9]+)', ?n) strConcat('order ', ?n, ?label)\n"
                  "      -> (?o ex:number ?n) (?o ex:label ?label)]\n"
                  "[sk: (?o ex:code ?c) makeSkolem(?d, ?o, 'delivery') -> (?d ex:forOrder ?o)]\n"
                  "[sk2: (?o ex:number ?n) makeSkolem(?d, ?o, 'delivery') -> (?d ex:numbered ?n)]");
  const auto got = inferred(*r);
  EXPECT_TRUE(got.count("ex:o1 ex:number \"0042\" ."));
  EXPECT_TRUE(got.count("ex:o1 ex:label \"order 0042\" ."));
  EXPECT_FALSE(got.count("ex:o2 ex:label \"order bogus\" ."));
  // makeSkolem gives the same blank node for the same arguments, in any rule.
  TermId delivery = kNoTerm;
  for (TripleId id : r->inferred()) {
    const Triple t = r->store().at(id);
    if (d.term(t.p).text == "http://ex/forOrder" && d.term(t.o).text == "http://ex/o1") {
      delivery = t.s;
    }
  }
  ASSERT_NE(delivery, kNoTerm);
  EXPECT_EQ(d.kind(delivery), TermKind::blank);
  EXPECT_NE(r->store().find(Triple{delivery, d.iri("http://ex/numbered"), d.literal("0042")}), kNoTriple);
}

TEST_F(Reasoning, TermTestsNoValueAndPrint) {
  auto r =
      reason("ex:a ex:p ex:b . ex:a ex:p \"lit\" . ex:c ex:p ex:d . ex:c ex:q ex:e .",
             "[lit: (?x ex:p ?y) isLiteral(?y) -> (?x ex:hasLiteral ex:yes)]\n"
             "[res: (?x ex:p ?y) notLiteral(?y) bound(?y) unbound(?z) -> (?y ex:isResource ex:yes)]\n"
             "[nv: (?x ex:p ?y) noValue(?x, ex:q) notLiteral(?y) -> (?x ex:lacksQ ?y) print('lacks', ?x)]");
  EXPECT_EQ(inferred(*r), (std::set<std::string>{"ex:a ex:hasLiteral ex:yes .", "ex:b ex:isResource ex:yes .",
                                                 "ex:d ex:isResource ex:yes .", "ex:a ex:lacksQ ex:b ."}));
  EXPECT_EQ(printed, (std::vector<std::string>{"\"lacks\" <http://ex/a>"}));
}

TEST_F(Reasoning, HeadsFollowJenaInstantiation) {
  // An unbound head variable is a new blank node at every use; literal subjects are dropped.
  auto r =
      reason("ex:a ex:t 1 .", "[f: (?s ex:t ?v) -> (?s ex:fresh ?z) (?z ex:back ?s) (?v ex:litsubj ?s)]");
  const auto out = r->inferred();
  ASSERT_EQ(out.size(), 2U);
  const Triple fresh = r->store().at(out[0]);
  const Triple back = r->store().at(out[1]);
  EXPECT_EQ(d.kind(fresh.o), TermKind::blank);
  EXPECT_EQ(d.kind(back.s), TermKind::blank);
  EXPECT_NE(fresh.o, back.s);
}

TEST_F(Reasoning, AxiomsAndBuiltinOnlyBodies) {
  auto r = reason("ex:a ex:p ex:b .",
                  "[ax: -> (ex:Robot rdfs:subClassOf ex:Machine)]\n"
                  "[never: equal(1, 1) -> (ex:x ex:y ex:z)]");
  EXPECT_EQ(
      inferred(*r),
      (std::set<std::string>{"ex:Robot <http://www.w3.org/2000/01/rdf-schema#subClassOf> ex:Machine ."}));
}

TEST_F(Reasoning, ViolationsComeWithTheirExplanation) {
  auto r = reason(
      "ex:m1 ex:temp \"95.0\"^^xsd:double ; ex:max \"80.0\"^^xsd:double . ex:m2 ex:temp \"20.0\"^^xsd:double "
      "; ex:max \"80.0\"^^xsd:double .",
      "[tooHot: (?m ex:temp ?t) (?m ex:max ?x) greaterThan(?t, ?x) -> (?m rb:violation 'temperature above "
      "maximum')]");
  const auto v = r->violations();
  ASSERT_EQ(v.size(), 1U);
  EXPECT_EQ(d.term(v[0].triple.s).text, "http://ex/m1");
  ASSERT_NE(v[0].because.rule, nullptr);
  EXPECT_EQ(v[0].because.rule->name, "tooHot");
  const auto matched = testing::lines(d, testing::triples_of(*r, v[0].because.premises));
  EXPECT_EQ(matched,
            (std::set<std::string>{"ex:m1 ex:temp \"95.0\"^^<http://www.w3.org/2001/XMLSchema#double> .",
                                   "ex:m1 ex:max \"80.0\"^^<http://www.w3.org/2001/XMLSchema#double> ."}));
  EXPECT_FALSE(r->explain(v[0].because.premises[0]).has_value());  // data has no derivation
}

TEST_F(Reasoning, RunawayRulesStopAtTheLimit) {
  Reasoner r(d, testing::rules(d, "[grow: (?x ex:next ?y) -> (?y ex:next ?z)]"), ReasonerOptions{500, {}});
  r.add_data(testing::turtle(d, "ex:a ex:next ex:b ."));
  auto st = r.run();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::limit_exceeded);
  EXPECT_NE(st.error().message.find("'grow'"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("500"), std::string::npos);
  auto again = r.update(Changes{});
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().code, Errc::state);
}

TEST_F(Reasoning, RemoveDeletesTheMatchAndItsConsequences) {
  auto r =
      reason("ex:m ex:alarm ex:al1 . ex:al1 ex:acknowledged \"true\"^^xsd:boolean . ex:m ex:alarm ex:al2 .",
             "[alarm: (?m ex:alarm ?a) -> (?m ex:alarmed ?a)]\n"
             "[ack: (?m ex:alarm ?a) (?a ex:acknowledged 'true'^^xsd:boolean) -> remove(0)]");
  EXPECT_EQ(inferred(*r), (std::set<std::string>{"ex:m ex:alarmed ex:al2 ."}));
  EXPECT_EQ(r->store().find(Triple{d.iri("http://ex/m"), d.iri("http://ex/alarm"), d.iri("http://ex/al1")}),
            kNoTriple);
}

}  // namespace
}  // namespace sf::knowledge
