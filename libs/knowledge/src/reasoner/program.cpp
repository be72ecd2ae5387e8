#include "program.hpp"

#include <algorithm>

namespace sf::knowledge::engine {
namespace {

Slot slot(const RuleNode& n, const Dictionary& dict) {
  Slot s;
  s.is_var = n.is_var;
  s.var = n.var;
  if (!n.is_var) {
    s.term = n.term;
    s.vid = dict.value_id(n.term);
  }
  return s;
}

Pattern pattern(const TriplePattern& tp, std::uint32_t body_index, const Dictionary& dict) {
  return Pattern{body_index, slot(tp.s, dict), slot(tp.p, dict), slot(tp.o, dict)};
}

void index_no_value(Program& prog, const CompiledRule& r) {
  for (const BuiltinCall* g : r.guards) {
    if (g->op != Builtin::no_value) {
      continue;
    }
    const RuleNode& p = *no_value_args(*g).p;
    auto& list = p.is_var ? prog.no_value_any : prog.no_value_tests[p.term];
    if (std::find(list.begin(), list.end(), r.index) == list.end()) {
      list.push_back(r.index);
    }
  }
}

}  // namespace

NoValueArgs no_value_args(const BuiltinCall& call) {
  return NoValueArgs{&call.args[0], &call.args[1], call.args.size() > 2 ? &call.args[2] : nullptr};
}

Program compile(const RuleSet& rules, const Dictionary& dict) {
  Program prog;
  for (const Rule& rule : rules.rules) {
    CompiledRule r;
    r.rule = &rule;
    r.index = static_cast<std::uint32_t>(prog.rules.size());
    r.vars = static_cast<std::uint32_t>(rule.variables.size());
    r.monotonic = rule.monotonic();
    r.axiom = rule.body.empty();
    r.in_body.assign(r.vars, false);
    r.in_patterns.assign(r.vars, false);
    for (std::uint32_t i = 0; i < rule.body.size(); ++i) {
      if (const auto* tp = std::get_if<TriplePattern>(&rule.body[i])) {
        r.patterns.push_back(pattern(*tp, i, dict));
        for (const RuleNode* n : {&tp->s, &tp->p, &tp->o}) {
          if (n->is_var) {
            r.in_body[n->var] = true;
            r.in_patterns[n->var] = true;
          }
        }
      } else {
        r.guards.push_back(&std::get<BuiltinCall>(rule.body[i]));
        for (const RuleNode& n : r.guards.back()->args) {
          if (n.is_var) {
            r.in_body[n.var] = true;
          }
        }
        r.has_no_value = r.has_no_value || r.guards.back()->op == Builtin::no_value;
      }
    }
    for (const Clause& c : rule.head) {
      if (const auto* tp = std::get_if<TriplePattern>(&c)) {
        r.heads.push_back(pattern(*tp, 0, dict));
      } else {
        r.actions.push_back(&std::get<BuiltinCall>(c));
      }
    }
    for (std::uint32_t i = 0; i < r.patterns.size(); ++i) {
      const Slot& p = r.patterns[i].p;
      (p.is_var ? prog.wildcard_triggers : prog.triggers[p.term]).push_back(Ref{r.index, i});
    }
    for (std::uint32_t i = 0; i < r.heads.size(); ++i) {
      const Slot& p = r.heads[i].p;
      (p.is_var ? prog.wildcard_heads : prog.heads[p.term]).push_back(Ref{r.index, i});
    }
    index_no_value(prog, r);
    prog.rules.push_back(std::move(r));
  }
  return prog;
}

}  // namespace sf::knowledge::engine
