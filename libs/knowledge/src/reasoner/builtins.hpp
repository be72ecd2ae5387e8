// Body builtins of Jena's rule language, evaluated on a binding (the engine runs them in body
// order after the triple patterns have matched, as RETETerminal does).
#pragma once

#include <functional>
#include <optional>
#include <regex>
#include <string>
#include <unordered_map>

#include "matcher.hpp"

namespace sf::knowledge::engine {

class Builtins {
 public:
  Builtins(Dictionary& dict, const TripleStore& store, std::function<void(const std::string&)> print)
      : dict_(dict), store_(store), print_(std::move(print)) {}

  // Runs a body builtin; it may bind variables of env (sum's result, makeSkolem's node, ...).
  // Returns false when the guard fails. With skip_side_effects print() prints nothing.
  bool eval(const BuiltinCall& call, Env& env, bool skip_side_effects = false);
  // Runs the builtins of a rule body in order; false as soon as one fails.
  bool eval_all(const CompiledRule& r, Env& env, bool monotonic_only = false, bool skip_side_effects = false);
  // Only the non-monotonic guards (noValue), as Jena re-checks them before firing a deferred rule.
  bool still_holds(const CompiledRule& r, Env& env);
  // print() in a head.
  void print(const BuiltinCall& call, const Env& env);

 private:
  struct Operands {
    TermId a, b;
    const LiteralValue* va;  // nullptr unless a literal
    const LiteralValue* vb;
  };
  [[nodiscard]] TermId arg(const BuiltinCall& c, std::size_t i, const Env& env) const;
  [[nodiscard]] std::optional<Operands> operands(const BuiltinCall& c, const Env& env) const;
  bool bind(const RuleNode& n, TermId value, Env& env) const;
  bool compare(const BuiltinCall& c, const Env& env, bool (*accept)(int)) const;
  bool equal(const BuiltinCall& c, const Env& env) const;
  bool arithmetic(const BuiltinCall& c, Env& env);
  bool extremum(const BuiltinCall& c, Env& env, bool want_min);
  bool no_value(const BuiltinCall& c, const Env& env) const;
  bool regex(const BuiltinCall& c, Env& env);
  bool str_concat(const BuiltinCall& c, Env& env);
  bool make_skolem(const BuiltinCall& c, Env& env);
  [[nodiscard]] std::string lexical(TermId t) const;

  Dictionary& dict_;
  const TripleStore& store_;
  std::function<void(const std::string&)> print_;
  std::unordered_map<std::string, std::optional<std::regex>> regexes_;
};

}  // namespace sf::knowledge::engine
