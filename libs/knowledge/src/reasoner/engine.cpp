// Forward evaluation: semi-naive joins of each new triple, staged head triples, and the agenda
// of deferred non-monotonic rule matches (Jena RETEEngine.runAll / RETEConflictSet).
#include "engine.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {

using engine::CompiledRule;
using engine::Env;

namespace {

std::size_t max_vars(const engine::Program& p) {
  std::size_t n = 1;
  for (const auto& r : p.rules) {
    n = std::max<std::size_t>(n, r.vars);
  }
  return n;
}

std::size_t max_patterns(const engine::Program& p) {
  std::size_t n = 1;
  for (const auto& r : p.rules) {
    n = std::max(n, r.patterns.size());
  }
  return n;
}

std::function<void(const std::string&)> default_print(std::function<void(const std::string&)> print) {
  if (print) {
    return print;
  }
  return [](const std::string& line) { sf::log::get("knowledge")->info("print: {}", line); };
}

}  // namespace

Reasoner::Engine::Engine(Dictionary& dict, RuleSet rules, ReasonerOptions options)
    : dict_(dict),
      rules_(std::move(rules)),
      options_(std::move(options)),
      store_(dict),
      program_(engine::compile(rules_, dict)),
      matcher_(dict, store_),
      builtins_(dict, store_, default_print(options_.print)) {
  no_value_derived_.resize(program_.rules.size());
  env_.assign(max_vars(program_), kNoTerm);
  premises_.assign(max_patterns(program_), kNoTriple);
}

void Reasoner::Engine::add_data(std::span<const Triple> triples) {
  for (const Triple& t : triples) {
    const auto [id, inserted] = store_.insert(t);
    store_.set_flags(id, static_cast<std::uint8_t>(store_.flags(id) | kAsserted));
    if (inserted) {
      note_inserted(t.p);
    }
  }
}

Result<UpdateResult> Reasoner::Engine::run() {
  if (failed_) {
    return make_error(Errc::state, "the reasoner stopped at its derivation limit; build a new one");
  }
  if (ran_) {
    return UpdateResult{};
  }
  derived_ = 0;
  retracted_ = 0;
  // Jena's findAndProcessAxioms: rules with an empty body fire once.
  for (const CompiledRule& r : program_.rules) {
    if (r.axiom) {
      std::fill(env_.begin(), env_.end(), kNoTerm);
      stage_heads(r, env_, {});
      ++firings_;
    }
  }
  SF_TRY(apply_pending());
  SF_TRY(settle());
  ran_ = true;
  return UpdateResult{derived_, retracted_};
}

Result<UpdateResult> Reasoner::Engine::update(const Changes& changes) {
  if (!ran_) {
    auto first = run();
    if (!first) {
      return first.error();
    }
  }
  if (failed_) {
    return make_error(Errc::state, "the reasoner stopped at its derivation limit; build a new one");
  }
  derived_ = 0;
  retracted_ = 0;
  std::vector<TripleId> roots;
  for (const Triple& t : changes.remove) {
    const TripleId id = store_.find(t);
    if (id == kNoTriple || (store_.flags(id) & kAsserted) == 0) {
      continue;  // not data: derived triples come and go with their premises
    }
    store_.set_flags(id, static_cast<std::uint8_t>(store_.flags(id) & ~kAsserted));
    if (supported(id)) {
      continue;  // still derived
    }
    support_.drop(id);  // a record that went stale while the triple was data
    roots.push_back(id);
  }
  SF_TRY(retract(std::move(roots), true));
  add_data(changes.add);
  SF_TRY(settle());
  store_.compact_if_worthwhile();
  support_.compact_if_worthwhile();
  return UpdateResult{derived_, retracted_};
}

// A derived triple stays when the premises of its recorded derivation are all present: their
// own records reach further back (premises are always older), down to data.
bool Reasoner::Engine::supported(TripleId id) const {
  const auto* rec = support_.record_of(id);
  if (rec == nullptr) {
    return false;
  }
  for (TripleId p : support_.premises(*rec)) {
    if (!store_.alive(p)) {
      return false;
    }
  }
  return true;
}

Status Reasoner::Engine::saturate() {
  while (true) {
    SF_TRY(process_new_triples());
    if (agenda_.empty()) {
      return {};
    }
    Deferred d = std::move(agenda_.back());
    agenda_.pop_back();
    SF_TRY(fire_deferred(std::move(d)));
  }
}

Status Reasoner::Engine::process_new_triples() {
  while (watermark_ < store_.next_id()) {
    const TripleId id = watermark_++;
    if (store_.alive(id)) {
      join_triple(id);
      SF_TRY(apply_pending());
    }
  }
  return {};
}

void Reasoner::Engine::join_triple(TripleId id) {
  const TermId p = store_.at(id).p;
  const auto run_refs = [&](const std::vector<engine::Ref>& refs) {
    for (const engine::Ref& ref : refs) {
      const CompiledRule& r = program_.rules[ref.rule];
      matcher_.delta(
          r, ref.pattern, id, env_, premises_,
          [&](Env& env, const std::vector<TripleId>& premises) { return on_match(r, env, premises); });
    }
  };
  if (const auto* refs = program_.triggers_for(p)) {
    run_refs(*refs);
  }
  run_refs(program_.wildcard_triggers);
}

// A body match: run the builtins, then stage the head (monotonic rules) or defer the match.
bool Reasoner::Engine::on_match(const CompiledRule& r, Env& env, const std::vector<TripleId>& premises) {
  guard_env_ = env;
  if (!builtins_.eval_all(r, guard_env_)) {
    return false;
  }
  ++firings_;
  const std::span<const TripleId> matched(premises.data(), r.patterns.size());
  if (r.monotonic) {
    stage_heads(r, guard_env_, matched);
    for (const BuiltinCall* action : r.actions) {
      builtins_.print(*action, guard_env_);  // the only head action of a monotonic rule
    }
  } else {
    agenda_.push_back(Deferred{r.index, guard_env_, std::vector<TripleId>(matched.begin(), matched.end())});
  }
  return false;
}

// BindingVector.instantiate: an unbound variable becomes a new blank node at each use; triples
// with a literal subject are not recorded (RETEConflictSet.execute).
void Reasoner::Engine::stage_heads(const CompiledRule& r, const Env& env,
                                   std::span<const TripleId> premises) {
  const auto value = [&](const engine::Slot& s) {
    if (!s.is_var) {
      return s.term;
    }
    return env[s.var] != kNoTerm ? env[s.var] : dict_.fresh_blank();
  };
  for (const engine::Pattern& h : r.heads) {
    const Triple t{value(h.s), value(h.p), value(h.o)};
    if (dict_.is_literal(t.s)) {
      continue;
    }
    pending_.push_back(Pending{t, r.index, static_cast<std::uint32_t>(pending_premises_.size()),
                               static_cast<std::uint32_t>(premises.size())});
    pending_premises_.insert(pending_premises_.end(), premises.begin(), premises.end());
  }
}

Status Reasoner::Engine::fire_deferred(Deferred d) {
  const CompiledRule& r = program_.rules[d.rule];
  for (TripleId p : d.premises) {
    if (!store_.alive(p)) {
      return {};  // the match is gone (Jena cancels the +/- pair)
    }
  }
  if (!builtins_.still_holds(r, d.env)) {
    return {};
  }
  stage_heads(r, d.env, d.premises);
  std::vector<TripleId> removals;
  for (const BuiltinCall* action : r.actions) {
    if (action->op == Builtin::print) {
      builtins_.print(*action, d.env);
      continue;
    }
    for (const RuleNode& n : action->args) {  // remove(i...): the triples matched by body clause i
      const auto index = static_cast<std::uint32_t>(dict_.value(n.term)->decimal.mantissa);
      for (std::size_t k = 0; k < r.patterns.size(); ++k) {
        if (r.patterns[k].body_index == index && store_.alive(d.premises[k])) {
          removals.push_back(d.premises[k]);
        }
      }
    }
  }
  SF_TRY(apply_pending());
  if (!removals.empty()) {
    std::sort(removals.begin(), removals.end());
    removals.erase(std::unique(removals.begin(), removals.end()), removals.end());
    SF_TRY(retract(std::move(removals), false));
  }
  return {};
}

Status Reasoner::Engine::apply_pending() {
  Status status;
  std::size_t i = 0;
  for (; i < pending_.size() && status.ok(); ++i) {
    const Pending& p = pending_[i];
    const auto [id, inserted] = store_.insert(p.triple);
    if (!inserted) {
      continue;  // already present by value (RETERuleContext.contains)
    }
    store_.set_flags(id, kDerived);
    support_.set(id, p.rule, std::span<const TripleId>(pending_premises_.data() + p.offset, p.count));
    if (program_.rules[p.rule].has_no_value) {
      no_value_derived_[p.rule].push_back(id);
    }
    note_inserted(p.triple.p);
    status = derived_one_more(program_.rules[p.rule]);
  }
  pending_.clear();
  pending_premises_.clear();
  return status;
}

Status Reasoner::Engine::derived_one_more(const CompiledRule& r) {
  if (++derived_ <= options_.max_derived) {
    return {};
  }
  failed_ = true;
  agenda_.clear();
  return make_error(
      Errc::limit_exceeded,
      fmt::format("derivation limit reached: more than {} triples derived (last by rule '{}', {}); "
                  "the rules may not terminate, or the limit is too low for the data",
                  options_.max_derived, r.rule->label(), r.rule->pos.describe()));
}

void Reasoner::Engine::note_inserted(TermId predicate) {
  if (auto it = program_.no_value_tests.find(predicate); it != program_.no_value_tests.end()) {
    revalidate_.insert(it->second.begin(), it->second.end());
  }
  revalidate_.insert(program_.no_value_any.begin(), program_.no_value_any.end());
}

// Reasoner: the public face of the engine.

Reasoner::Reasoner(Dictionary& dict, RuleSet rules, ReasonerOptions options)
    : engine_(std::make_unique<Engine>(dict, std::move(rules), std::move(options))) {}

Reasoner::~Reasoner() = default;

void Reasoner::add_data(std::span<const Triple> triples) {
  engine_->add_data(triples);
}

Result<UpdateResult> Reasoner::run() {
  return engine_->run();
}
Result<UpdateResult> Reasoner::update(const Changes& changes) {
  return engine_->update(changes);
}

Result<UpdateResult> Reasoner::set_value(TermId s, TermId p, TermId o) {
  Changes changes;
  bool present = false;
  engine_->store_.match(ValuePattern{s, p, kNoTerm}, engine_->store_.next_id(), [&](TripleId id) {
    if ((engine_->store_.flags(id) & kAsserted) == 0) {
      return;
    }
    const Triple t = engine_->store_.at(id);
    if (engine_->dict_.value_id(t.o) == engine_->dict_.value_id(o)) {
      present = true;
    } else {
      changes.remove.push_back(t);
    }
  });
  if (!present) {
    changes.add.push_back(Triple{s, p, o});
  }
  return update(changes);
}

const TripleStore& Reasoner::store() const {
  return engine_->store_;
}
const Dictionary& Reasoner::dictionary() const {
  return engine_->dict_;
}
const RuleSet& Reasoner::rules() const {
  return engine_->rules_;
}

std::vector<TripleId> Reasoner::inferred() const {
  std::vector<TripleId> out;
  const TripleStore& st = engine_->store_;
  for (TripleId id = 0; id < st.next_id(); ++id) {
    if (st.alive(id) && (st.flags(id) & kDerived) != 0 && (st.flags(id) & kAsserted) == 0) {
      out.push_back(id);
    }
  }
  return out;
}

std::optional<Derivation> Reasoner::explain(TripleId id) const {
  const auto* rec = engine_->support_.record_of(id);
  if (rec == nullptr || !engine_->store_.alive(id)) {
    return std::nullopt;
  }
  const auto premises = engine_->support_.premises(*rec);
  return Derivation{&engine_->rules_.rules[rec->rule],
                    std::vector<TripleId>(premises.begin(), premises.end())};
}

std::vector<Violation> Reasoner::violations() const {
  std::vector<Violation> out;
  const TermId violation = engine_->dict_.find(TermKind::iri, vocab::kRbViolation);
  if (violation == kNoTerm) {
    return out;
  }
  for (TripleId id : inferred()) {
    const Triple t = engine_->store_.at(id);
    if (t.p == violation) {
      out.push_back(Violation{id, t, explain(id).value_or(Derivation{})});
    }
  }
  return out;
}

ReasonerStats Reasoner::stats() const {
  ReasonerStats s;
  const TripleStore& st = engine_->store_;
  for (TripleId id = 0; id < st.next_id(); ++id) {
    if (!st.alive(id)) {
      continue;
    }
    if ((st.flags(id) & kAsserted) != 0) {
      ++s.asserted;
    } else {
      ++s.inferred;
    }
  }
  s.firings = engine_->firings_;
  s.memory_bytes = engine_->dict_.memory_bytes() + st.memory_bytes() + engine_->support_.memory_bytes();
  return s;
}

}  // namespace sf::knowledge
