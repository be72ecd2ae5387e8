// The reasoner's state and evaluation loop (see reasoner.hpp for the semantics).
#pragma once

#include <unordered_set>

#include "builtins.hpp"
#include "matcher.hpp"
#include "program.hpp"
#include "sf/knowledge/reasoner.hpp"
#include "support.hpp"

namespace sf::knowledge {

class Reasoner::Engine {
 public:
  Engine(Dictionary& dict, RuleSet rules, ReasonerOptions options);

  void add_data(std::span<const Triple> triples);
  Result<UpdateResult> run();
  Result<UpdateResult> update(const Changes& changes);

  Dictionary& dict_;
  RuleSet rules_;
  ReasonerOptions options_;
  TripleStore store_;
  engine::Program program_;
  engine::Matcher matcher_;
  engine::Builtins builtins_;
  engine::Support support_;
  std::size_t firings_ = 0;

 private:
  // A match of a non-monotonic rule waiting to fire (Jena's conflict set entry).
  struct Deferred {
    std::uint32_t rule;
    engine::Env env;
    std::vector<TripleId> premises;
  };
  // A head triple waiting to be inserted with its derivation.
  struct Pending {
    Triple triple;
    std::uint32_t rule;
    std::uint32_t offset;  // into pending_premises_
    std::uint32_t count;
  };

  // Forward chaining from the watermark until nothing is waiting, deferred rules included.
  Status saturate();
  Status process_new_triples();
  void join_triple(TripleId id);
  bool on_match(const engine::CompiledRule& r, engine::Env& env, const std::vector<TripleId>& premises);
  void stage_heads(const engine::CompiledRule& r, const engine::Env& env, std::span<const TripleId> premises);
  Status fire_deferred(Deferred d);
  Status apply_pending();
  Status derived_one_more(const engine::CompiledRule& r);
  void note_inserted(TermId predicate);
  [[nodiscard]] bool supported(TripleId id) const;

  // Truth maintenance (maintenance.cpp).
  Status settle();
  Status retract(std::vector<TripleId> roots, bool rederive_roots);
  bool rederive(const Triple& t);
  Result<bool> revalidate_no_value();
  bool rerun_unblocked();
  void note_erased(const Triple& t);

  TripleId watermark_ = 0;  // every triple below it has been joined
  bool ran_ = false;
  bool failed_ = false;
  std::size_t derived_ = 0;  // in the current operation
  std::size_t retracted_ = 0;
  std::vector<Deferred> agenda_;
  std::vector<Pending> pending_;
  std::vector<TripleId> pending_premises_;
  std::vector<TripleId> pending_removals_;
  std::vector<std::vector<TripleId>> no_value_derived_;  // per rule: triples it derived (noValue rules)
  std::unordered_set<std::uint32_t> revalidate_;         // noValue rules whose tested predicate grew
  std::vector<Triple> erased_;                           // erased triples that may unblock noValue
  engine::Env env_;
  engine::Env guard_env_;
  std::vector<TripleId> premises_;
};

}  // namespace sf::knowledge
