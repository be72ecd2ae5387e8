// Forward-chaining rule engine over the triple store, with the semantics of Jena's
// GenericRuleReasoner in FORWARD_RETE mode (Jena "Reasoners and rule engines", §Forward
// chaining engine):
//  - a rule fires once per distinct match of its body triple patterns, after which its body
//    builtins run in order; head triples already present by value are not added again, head
//    triples with a literal subject are dropped, unbound head variables become fresh blank nodes;
//  - non-monotonic rules (noValue, remove) are deferred to an agenda fired last-in first-out
//    once no new triple is waiting, re-checking their noValue guards first (RETEConflictSet).
// Evaluation is semi-naive, tuple at a time: triple n joins only with triples older than n, so
// each match is found exactly once, without RETE's partial-match memories.
//
// After the first run() the closure is maintained incrementally (delete and re-derive): asserting
// or retracting data, or replacing a live value, derives what follows and retracts the derived
// triples that lose their support, including conclusions of noValue guards that now fail.
// Every derived triple keeps the derivation that produced it (rule and matched triples).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/knowledge/rules.hpp"
#include "sf/knowledge/store.hpp"

namespace sf::knowledge {

struct ReasonerOptions {
  // Stops a run() or update that derives more triples than this: rules that never terminate
  // (e.g. one making a fresh blank node from each result) fail with Errc::limit_exceeded.
  std::size_t max_derived = 10'000'000;
  // Receives the output of print(); by default it goes to the "knowledge" logger.
  std::function<void(const std::string&)> print;
};

struct Derivation {
  const Rule* rule = nullptr;
  std::vector<TripleId> premises;  // the triples matched by the body patterns, in body order
};

struct Violation {
  TripleId id = kNoTriple;  // the (subject rb:violation message) triple
  Triple triple;
  Derivation because;
};

struct Changes {
  std::vector<Triple> add;
  std::vector<Triple> remove;
};

struct UpdateResult {
  std::size_t derived = 0;    // triples the rules added
  std::size_t retracted = 0;  // derived triples removed because they lost their support
};

struct ReasonerStats {
  std::size_t asserted = 0;  // data triples
  std::size_t inferred = 0;  // derived triples that are not data
  std::size_t firings = 0;   // rule matches whose builtins passed
  std::size_t memory_bytes = 0;
};

class Reasoner {
 public:
  Reasoner(Dictionary& dict, RuleSet rules, ReasonerOptions options = {});
  ~Reasoner();
  Reasoner(const Reasoner&) = delete;
  Reasoner& operator=(const Reasoner&) = delete;

  // Data before the first run() (afterwards, update() keeps the closure up to date).
  void add_data(std::span<const Triple> triples);
  // Computes the closure of the data under the rules.
  Result<UpdateResult> run();
  // Applies data changes to the closure (runs first if run() was not called yet). Removals
  // are applied before additions.
  Result<UpdateResult> update(const Changes& changes);
  // A live value: replaces every (s p *) by (s p o).
  Result<UpdateResult> set_value(TermId s, TermId p, TermId o);

  [[nodiscard]] const TripleStore& store() const;
  [[nodiscard]] const Dictionary& dictionary() const;
  [[nodiscard]] const RuleSet& rules() const;
  // Derived triples that are not data (Jena's deductions graph), in derivation order.
  [[nodiscard]] std::vector<TripleId> inferred() const;
  // Every derived (s rb:violation o) with its explanation.
  [[nodiscard]] std::vector<Violation> violations() const;
  // How a derived triple was derived; nothing for data.
  [[nodiscard]] std::optional<Derivation> explain(TripleId id) const;
  [[nodiscard]] ReasonerStats stats() const;

 private:
  class Engine;
  std::unique_ptr<Engine> engine_;
};

}  // namespace sf::knowledge
