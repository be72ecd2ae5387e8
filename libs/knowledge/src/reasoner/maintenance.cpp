// Truth maintenance by delete and re-derive (Gupta, Mumick, Subrahmanian, "Maintaining views
// incrementally", SIGMOD 1993): retracting a triple removes every derived triple whose recorded
// derivation depends on it, then re-derives those that still follow from what remains in one
// step; forward chaining from the re-derived triples restores the rest. noValue conclusions are
// re-checked when their tested predicate grows, and re-derived when it shrinks.
#include <algorithm>

#include "engine.hpp"

namespace sf::knowledge {

using engine::CompiledRule;
using engine::Env;

Status Reasoner::Engine::settle() {
  while (true) {
    SF_TRY(saturate());
    auto retracted = revalidate_no_value();
    if (!retracted) {
      return retracted.error();
    }
    if (*retracted) {
      continue;
    }
    if (rerun_unblocked()) {
      continue;
    }
    return {};
  }
}

Status Reasoner::Engine::retract(std::vector<TripleId> roots, bool rederive_roots) {
  if (roots.empty()) {
    return {};
  }
  // Over-delete: everything whose recorded derivation leans on a doomed triple, transitively.
  std::unordered_set<TripleId> doomed(roots.begin(), roots.end());
  std::vector<TripleId> order = roots;
  for (std::size_t i = 0; i < order.size(); ++i) {
    support_.for_each_dependent(order[i], [&](TripleId h) {
      if (store_.alive(h) && (store_.flags(h) & kAsserted) == 0 && doomed.insert(h).second) {
        order.push_back(h);
      }
    });
  }
  std::vector<Triple> victims;
  victims.reserve(order.size());
  for (TripleId id : order) {
    const Triple t = store_.at(id);
    victims.push_back(t);
    support_.drop(id);
    store_.erase(id);
    note_erased(t);
  }
  // Re-derive in one step from what is left; forward chaining does the rest.
  for (std::size_t i = 0; i < victims.size(); ++i) {
    const bool root = i < roots.size();
    const bool back = (!root || rederive_roots) && rederive(victims[i]);
    if (!root && !back) {
      ++retracted_;  // a derived triple that lost its support
    }
  }
  return apply_pending();
}

// Looks for one match of a rule whose head can produce t; stages t with it.
bool Reasoner::Engine::rederive(const Triple& t) {
  const TermId vo = dict_.value_id(t.o);
  const auto unify = [&](const engine::Slot& s, TermId term, TermId value, const CompiledRule& r, Env& env) {
    if (!s.is_var) {
      return s.vid == value;
    }
    if (!r.in_body[s.var]) {
      return false;  // a fresh blank node in the head: cannot be this triple
    }
    if (env[s.var] == kNoTerm) {
      env[s.var] = term;
      return true;
    }
    return dict_.value_id(env[s.var]) == value;
  };
  const auto try_refs = [&](const std::vector<engine::Ref>& refs) {
    for (const engine::Ref& ref : refs) {
      const CompiledRule& r = program_.rules[ref.rule];
      const engine::Pattern& h = r.heads[ref.pattern];
      Env env(r.vars, kNoTerm);
      if (!unify(h.s, t.s, dict_.value_id(t.s), r, env) || !unify(h.p, t.p, dict_.value_id(t.p), r, env) ||
          !unify(h.o, t.o, vo, r, env)) {
        continue;
      }
      if (r.axiom) {
        pending_.push_back(Pending{t, r.index, static_cast<std::uint32_t>(pending_premises_.size()), 0});
        return true;
      }
      if (r.patterns.empty()) {
        continue;  // builtins only: never fires (Jena compiles no RETE node for it)
      }
      std::vector<TripleId> premises(r.patterns.size(), kNoTriple);
      const bool found = matcher_.solve(r, env, premises, [&](Env& e, const std::vector<TripleId>& matched) {
        guard_env_ = e;
        if (!builtins_.eval_all(r, guard_env_, false, true)) {
          return false;
        }
        pending_.push_back(Pending{t, r.index, static_cast<std::uint32_t>(pending_premises_.size()),
                                   static_cast<std::uint32_t>(matched.size())});
        pending_premises_.insert(pending_premises_.end(), matched.begin(), matched.end());
        return true;
      });
      if (found) {
        return true;
      }
    }
    return false;
  };
  if (auto it = program_.heads.find(t.p); it != program_.heads.end() && try_refs(it->second)) {
    return true;
  }
  return try_refs(program_.wildcard_heads);
}

// A tested predicate grew: conclusions of noValue rules whose guard now fails lose support.
Result<bool> Reasoner::Engine::revalidate_no_value() {
  if (revalidate_.empty()) {
    return false;
  }
  std::vector<std::uint32_t> rules(revalidate_.begin(), revalidate_.end());
  revalidate_.clear();
  std::sort(rules.begin(), rules.end());
  std::vector<TripleId> doomed;
  for (std::uint32_t ri : rules) {
    const CompiledRule& r = program_.rules[ri];
    auto& derived = no_value_derived_[ri];
    std::erase_if(derived, [&](TripleId id) {
      const auto* rec = support_.record_of(id);
      return !store_.alive(id) || rec == nullptr || rec->rule != ri;
    });
    Env env(r.vars, kNoTerm);
    for (TripleId id : derived) {
      if (!matcher_.rebind(r, support_.premises(*support_.record_of(id)), env) ||
          !builtins_.eval_all(r, env, false, true)) {
        doomed.push_back(id);
      }
    }
  }
  if (doomed.empty()) {
    return false;
  }
  SF_TRY(retract(std::move(doomed), true));
  return true;
}

// A tested predicate shrank: matches that its triples blocked may fire now.
bool Reasoner::Engine::rerun_unblocked() {
  if (erased_.empty()) {
    return false;
  }
  std::vector<Triple> erased;
  erased.swap(erased_);
  const std::size_t before = agenda_.size();
  for (const Triple& t : erased) {
    std::vector<std::uint32_t> rules = program_.no_value_any;
    if (auto it = program_.no_value_tests.find(t.p); it != program_.no_value_tests.end()) {
      rules.insert(rules.end(), it->second.begin(), it->second.end());
    }
    for (std::uint32_t ri : rules) {
      const CompiledRule& r = program_.rules[ri];
      for (const BuiltinCall* g : r.guards) {
        if (g->op != Builtin::no_value || r.patterns.empty()) {
          continue;
        }
        // Restrict the search to matches whose guard this triple blocked.
        const auto args = engine::no_value_args(*g);
        Env env(r.vars, kNoTerm);
        bool fits = true;
        const auto restrict = [&](const RuleNode* n, TermId value, bool object) {
          if (n == nullptr) {
            return;
          }
          if (!n->is_var) {
            fits = fits && (object ? dict_.value_id(n->term) == dict_.value_id(value) : n->term == value);
          } else if (r.in_patterns[n->var]) {
            fits = fits && (env[n->var] == kNoTerm || dict_.value_id(env[n->var]) == dict_.value_id(value));
            env[n->var] = value;
          }
        };
        restrict(args.s, t.s, false);
        restrict(args.p, t.p, false);
        restrict(args.o, t.o, true);
        if (!fits) {
          continue;
        }
        std::vector<TripleId> premises(r.patterns.size(), kNoTriple);
        matcher_.solve(r, env, premises, [&](Env& e, const std::vector<TripleId>& matched) {
          guard_env_ = e;
          if (builtins_.eval_all(r, guard_env_, false, true)) {
            agenda_.push_back(Deferred{ri, guard_env_, matched});
          }
          return false;
        });
      }
    }
  }
  return agenda_.size() > before;
}

void Reasoner::Engine::note_erased(const Triple& t) {
  if (!program_.no_value_any.empty() || program_.no_value_tests.count(t.p) != 0) {
    erased_.push_back(t);
  }
}

}  // namespace sf::knowledge
