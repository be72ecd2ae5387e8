// Rules in Apache Jena's rule syntax (Jena "Reasoners and rule engines", §Rule syntax and
// structure): `@prefix p: <iri>.`, comment lines starting with # or //, and forward rules
// `[name: body -> head]` (or unbracketed, ending with "."), whose clauses are triple patterns
// `(?s p ?o)` and builtin calls `name(args)`. Literals are '...' or "..." with an optional
// ^^datatype; bare numbers are xsd:int, or xsd:float with a decimal point, as in Jena.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/knowledge/term.hpp"

namespace sf::knowledge {

struct SourcePos {
  std::string file;
  int line = 0;
  int column = 0;
  [[nodiscard]] std::string describe() const;  // "file:line:column"
};

// A variable (index into the rule's variables) or a constant term.
struct RuleNode {
  bool is_var = false;
  std::uint32_t var = 0;
  TermId term = kNoTerm;

  static RuleNode variable(std::uint32_t index) { return RuleNode{true, index, kNoTerm}; }
  static RuleNode constant(TermId t) { return RuleNode{false, 0, t}; }
};

struct TriplePattern {
  RuleNode s, p, o;
};

// The builtins of Jena's BuiltinRegistry the engine implements.
enum class Builtin : std::uint8_t {
  equal,
  not_equal,
  less_than,
  greater_than,
  le,
  ge,  // comparisons
  sum,
  difference,
  product,
  quotient,
  min,
  max,  // arithmetic, last argument is the result
  no_value,
  regex,
  str_concat,
  make_skolem,  // graph test, strings, Skolem nodes
  is_literal,
  not_literal,
  bound,
  unbound,  // term tests
  print,
  remove,  // actions
};

struct BuiltinCall {
  Builtin op{};
  std::vector<RuleNode> args;
  SourcePos pos;
};

using Clause = std::variant<TriplePattern, BuiltinCall>;

struct Rule {
  std::string name;  // may be empty
  SourcePos pos;
  std::vector<Clause> body;
  std::vector<Clause> head;
  std::vector<std::string> variables;  // "?x", indexed by RuleNode::var

  // noValue in the body or remove in the head (Jena's Builtin.isMonotonic() == false).
  [[nodiscard]] bool monotonic() const;
  // The name, or "rule at file:line" for an anonymous rule.
  [[nodiscard]] std::string label() const;
};

struct RuleSet {
  std::vector<Rule> rules;
};

// Jena's builtin name ("lessThan") and back.
std::string_view builtin_name(Builtin b);

// Parses rules; any error yields "file:line:column: message" and no rules.
Result<RuleSet> parse_rules(std::string_view text, std::string_view file, Dictionary& dict);
Result<RuleSet> read_rules_file(const std::string& path, Dictionary& dict);

// The rule in Jena syntax, for explanations.
std::string format_rule(const Rule& rule, const Dictionary& dict);

}  // namespace sf::knowledge
