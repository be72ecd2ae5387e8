// Joins a rule's body patterns against the store, at each step taking the pattern with the
// fewest candidates under the bindings so far (index chain lengths). Two entry points:
//  - delta(): the matches in which one pattern is a given new triple and the other patterns use
//    older triples (semi-naive evaluation: each match is found once, when its newest triple is
//    processed; a triple matching several patterns counts for the first of them);
//  - solve(): every match extending a partial binding, over all triples (re-derivation checks
//    and noValue re-evaluation).
// The callback gets the bindings and the matched triple of each pattern and returns true to stop
// the search; it must not change the store (it may intern terms).
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "program.hpp"

namespace sf::knowledge::engine {

using Env = std::vector<TermId>;  // per rule variable, kNoTerm when unbound

class Matcher {
 public:
  Matcher(const Dictionary& dict, const TripleStore& store) : dict_(dict), store_(store) {}

  template <typename F>
  bool delta(const CompiledRule& r, std::uint32_t seed, TripleId id, Env& env,
             std::vector<TripleId>& premises, F&& on_match) {
    std::fill(env.begin(), env.end(), kNoTerm);
    Bound ignored;
    if (!constants_match(r.patterns[seed], id) || !bind(r.patterns[seed], id, env, ignored)) {
      return false;
    }
    premises[seed] = id;
    const std::uint64_t all = (std::uint64_t{1} << r.patterns.size()) - 1;  // at most 63 patterns
    return step(r, all & ~(std::uint64_t{1} << seed), Limit{seed, id}, env, premises, on_match);
  }

  template <typename F>
  bool solve(const CompiledRule& r, Env& env, std::vector<TripleId>& premises, F&& on_match) {
    const std::uint64_t all = (std::uint64_t{1} << r.patterns.size()) - 1;
    return step(r, all, Limit{kNone, store_.next_id()}, env, premises, on_match);
  }

  // Rebuilds the bindings of a recorded match from its premises (one per body pattern).
  bool rebind(const CompiledRule& r, std::span<const TripleId> premises, Env& env) const {
    std::fill(env.begin(), env.end(), kNoTerm);
    Bound ignored;
    for (std::size_t i = 0; i < r.patterns.size() && i < premises.size(); ++i) {
      if (!store_.alive(premises[i]) || !constants_match(r.patterns[i], premises[i]) ||
          !bind(r.patterns[i], premises[i], env, ignored)) {
        return false;
      }
    }
    return premises.size() == r.patterns.size();
  }

  // The store pattern of a body pattern under env: constants and bound variables by value id.
  [[nodiscard]] ValuePattern lookup(const Pattern& p, const Env& env) const {
    return ValuePattern{position(p.s, env), position(p.p, env), object_position(p.o, env)};
  }

 private:
  TermId position(const Slot& s, const Env& env) const { return s.is_var ? env[s.var] : s.term; }
  TermId object_position(const Slot& s, const Env& env) const {
    if (!s.is_var) {
      return s.vid;
    }
    return env[s.var] == kNoTerm ? kNoTerm : dict_.value_id(env[s.var]);
  }

  // Variables bound by one pattern, to be unbound again after the recursion.
  struct Bound {
    std::uint32_t vars[3] = {0, 0, 0};
    int n = 0;
    void undo(Env& env) const {
      for (int i = 0; i < n; ++i) {
        env[vars[i]] = kNoTerm;
      }
    }
  };

  bool constants_match(const Pattern& p, TripleId id) const {
    const Triple t = store_.at(id);
    return (p.s.is_var || p.s.term == t.s) && (p.p.is_var || p.p.term == t.p) &&
           (p.o.is_var || p.o.vid == store_.object_value(id));
  }

  // Binds the pattern's unbound variables to triple id; checks repeated variables by value.
  bool bind(const Pattern& p, TripleId id, Env& env, Bound& bound) const {
    bound.n = 0;
    const Triple t = store_.at(id);
    const TermId values[3] = {t.s, t.p, store_.object_value(id)};
    const TermId terms[3] = {t.s, t.p, t.o};
    const Slot* slots[3] = {&p.s, &p.p, &p.o};
    for (int i = 0; i < 3; ++i) {
      const Slot& s = *slots[i];
      if (!s.is_var) {
        continue;  // constants were part of the lookup
      }
      if (env[s.var] == kNoTerm) {
        env[s.var] = terms[i];
        bound.vars[bound.n++] = s.var;
      } else if (dict_.value_id(env[s.var]) != values[i]) {
        return false;
      }
    }
    return true;
  }

  // Which triples a pattern may use: in delta(), those before the seed pattern strictly older than
  // the seed triple, those after it up to and including it; in solve(), all of them.
  struct Limit {
    std::uint32_t seed;
    TripleId id;
    [[nodiscard]] TripleId for_pattern(std::uint32_t pi) const {
      return seed == kNone || pi < seed ? id : id + 1;
    }
  };

  // The remaining pattern with the fewest candidates under the current bindings; a single
  // remaining pattern needs no estimate. Returns false when some pattern has no candidate.
  bool choose(const CompiledRule& r, std::uint64_t remaining, const Env& env, std::uint32_t& best) const {
    if ((remaining & (remaining - 1)) == 0) {
      best = static_cast<std::uint32_t>(__builtin_ctzll(remaining));
      return true;
    }
    std::size_t best_count = ~std::size_t{0};
    for (std::uint64_t m = remaining; m != 0; m &= m - 1) {
      const auto i = static_cast<std::uint32_t>(__builtin_ctzll(m));
      const std::size_t n = store_.estimate(lookup(r.patterns[i], env));
      if (n == 0) {
        return false;
      }
      if (n < best_count) {
        best = i;
        best_count = n;
      }
    }
    return true;
  }

  template <typename F>
  bool step(const CompiledRule& r, std::uint64_t remaining, const Limit& limit, Env& env,
            std::vector<TripleId>& premises, F& on_match) {
    if (remaining == 0) {
      return on_match(env, premises);
    }
    std::uint32_t pi = 0;
    if (!choose(r, remaining, env, pi)) {
      return false;
    }
    const Pattern& p = r.patterns[pi];
    const std::uint64_t rest = remaining & ~(std::uint64_t{1} << pi);
    return store_.match(lookup(p, env), limit.for_pattern(pi), [&](TripleId id) {
      Bound newly;
      bool stop = false;
      if (bind(p, id, env, newly)) {
        premises[pi] = id;
        stop = step(r, rest, limit, env, premises, on_match);
      }
      newly.undo(env);
      return stop;
    });
  }

  const Dictionary& dict_;
  const TripleStore& store_;
};

}  // namespace sf::knowledge::engine
