// Rules compiled for the engine: body patterns with value ids of their constants, and the
// indexes from a predicate to the rules it can trigger, the head patterns that can produce it
// and the noValue guards that test it.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "sf/knowledge/rules.hpp"
#include "sf/knowledge/store.hpp"

namespace sf::knowledge::engine {

inline constexpr std::uint32_t kNone = 0xFFFFFFFFu;

struct Slot {
  bool is_var = false;
  std::uint32_t var = 0;
  TermId term = kNoTerm;  // constant term
  TermId vid = kNoTerm;   // its value id
};

struct Pattern {
  std::uint32_t body_index = 0;  // position among all body clauses (remove() counts these)
  Slot s, p, o;
};

struct CompiledRule {
  const Rule* rule = nullptr;
  std::uint32_t index = 0;
  std::vector<Pattern> patterns;            // body triple patterns in body order
  std::vector<const BuiltinCall*> guards;   // body builtins in body order
  std::vector<Pattern> heads;               // head triple patterns
  std::vector<const BuiltinCall*> actions;  // head builtins (print, remove)
  std::uint32_t vars = 0;
  std::vector<bool> in_body;      // per variable: occurs in the body (else a head use is a fresh blank node)
  std::vector<bool> in_patterns;  // per variable: occurs in a body triple pattern
  bool monotonic = true;
  bool axiom = false;  // empty body: fires once at start (Jena's findAndProcessAxioms)
  bool has_no_value = false;
};

struct Ref {
  std::uint32_t rule = 0;
  std::uint32_t pattern = 0;
};

struct Program {
  std::vector<CompiledRule> rules;
  std::unordered_map<TermId, std::vector<Ref>> triggers;  // body patterns by constant predicate
  std::vector<Ref> wildcard_triggers;                     // body patterns with a variable predicate
  std::unordered_map<TermId, std::vector<Ref>> heads;     // head patterns by constant predicate
  std::vector<Ref> wildcard_heads;
  std::unordered_map<TermId, std::vector<std::uint32_t>> no_value_tests;  // rules testing a predicate
  std::vector<std::uint32_t> no_value_any;                                // ... with a variable one

  [[nodiscard]] const std::vector<Ref>* triggers_for(TermId p) const {
    auto it = triggers.find(p);
    return it == triggers.end() ? nullptr : &it->second;
  }
};

// Compiles every rule of the set (the set must outlive the program).
Program compile(const RuleSet& rules, const Dictionary& dict);

// The argument positions of noValue(s, p[, o]).
struct NoValueArgs {
  const RuleNode* s;
  const RuleNode* p;
  const RuleNode* o;  // nullptr in the two-argument form
};
NoValueArgs no_value_args(const BuiltinCall& call);

}  // namespace sf::knowledge::engine
