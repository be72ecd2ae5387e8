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

// How constrained a pattern is once `bound` variables are known: the predicate counts most
// (every index starts from it), then subject and object.
int boundness(const Pattern& p, const std::vector<bool>& bound) {
  const auto is_bound = [&](const Slot& s) { return !s.is_var || bound[s.var]; };
  return (is_bound(p.p) ? 4 : 0) + (is_bound(p.s) ? 3 : 0) + (is_bound(p.o) ? 2 : 0);
}

void mark(const Pattern& p, std::vector<bool>& bound) {
  for (const Slot* s : {&p.s, &p.p, &p.o}) {
    if (s->is_var) {
      bound[s->var] = true;
    }
  }
}

// Greedy join order starting from the seed pattern: always the most bound pattern next.
std::vector<std::uint32_t> plan_from(const CompiledRule& r, std::uint32_t seed) {
  std::vector<bool> bound(r.vars, false);
  mark(r.patterns[seed], bound);
  std::vector<std::uint32_t> rest;
  for (std::uint32_t i = 0; i < r.patterns.size(); ++i) {
    if (i != seed) {
      rest.push_back(i);
    }
  }
  std::vector<std::uint32_t> order;
  while (!rest.empty()) {
    auto best = std::max_element(rest.begin(), rest.end(), [&](std::uint32_t a, std::uint32_t b) {
      return boundness(r.patterns[a], bound) < boundness(r.patterns[b], bound);
    });
    order.push_back(*best);
    mark(r.patterns[*best], bound);
    rest.erase(best);
  }
  return order;
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
      r.plans.push_back(plan_from(r, i));
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
