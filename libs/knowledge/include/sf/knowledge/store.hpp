// The in-memory triple store: triples of TermIds, numbered in insertion order, with the indexes
// the reasoner joins on — by (predicate, subject), (predicate, object), predicate, subject and
// object — kept as chains threaded through the triples (one 32-bit link per index per triple)
// in ascending id order, so "the matches older than triple n" is a prefix of a chain.
// Objects are indexed by value id, so literals match by value (Jena's sameValueAs); a triple
// whose values are already present is not stored twice.
#pragma once

#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "sf/knowledge/term.hpp"

namespace sf::knowledge {

using TripleId = std::uint32_t;
inline constexpr TripleId kNoTriple = 0xFFFFFFFFu;

struct Triple {
  TermId s = kNoTerm;
  TermId p = kNoTerm;
  TermId o = kNoTerm;
  bool operator==(const Triple&) const = default;
};

// Subject, predicate and the object's value id; kNoTerm is a wildcard.
struct ValuePattern {
  TermId s = kNoTerm;
  TermId p = kNoTerm;
  TermId o = kNoTerm;
};

// Per-triple flags kept by the store for its users.
enum TripleFlag : std::uint8_t {
  kAlive = 1,
  kAsserted = 2,  // given as data (not only derived)
  kDerived = 4,   // produced by a rule
};

class TripleStore {
 public:
  explicit TripleStore(const Dictionary& dict);
  ~TripleStore();
  TripleStore(const TripleStore&) = delete;
  TripleStore& operator=(const TripleStore&) = delete;

  // Adds t unless a triple with the same subject, predicate and object value is present;
  // returns the id of the stored triple and whether it was added now.
  std::pair<TripleId, bool> insert(const Triple& t);
  // The alive triple with t's values, or kNoTriple.
  [[nodiscard]] TripleId find(const Triple& t) const;
  void erase(TripleId id);

  [[nodiscard]] bool alive(TripleId id) const { return (flags_[id] & kAlive) != 0; }
  [[nodiscard]] std::uint8_t flags(TripleId id) const { return flags_[id]; }
  void set_flags(TripleId id, std::uint8_t f) {
    flags_[id] = static_cast<std::uint8_t>(f | (flags_[id] & kAlive));
  }
  [[nodiscard]] Triple at(TripleId id) const { return Triple{recs_[id].s, recs_[id].p, recs_[id].o}; }
  [[nodiscard]] TermId object_value(TripleId id) const { return recs_[id].vo; }
  [[nodiscard]] std::size_t size() const { return alive_; }
  // The id the next inserted triple gets; every id below it has been used.
  [[nodiscard]] TripleId next_id() const { return static_cast<TripleId>(recs_.size()); }

  // Calls f(id) for every alive triple matching p whose id is below limit, in ascending id order.
  // If f returns bool, true stops the scan; match() then returns true.
  template <typename F>
  bool match(const ValuePattern& p, TripleId limit, F&& f) const {
    const Scan sc = scan(p);
    const auto end = static_cast<TripleId>(recs_.size());
    for (TripleId id = sc.first; id != kNoTriple && id < limit && id < end; id = advance(sc, id)) {
      const Rec& r = recs_[id];
      if ((flags_[id] & kAlive) == 0 || (p.s != kNoTerm && r.s != p.s) || (p.p != kNoTerm && r.p != p.p) ||
          (p.o != kNoTerm && r.vo != p.o)) {
        continue;
      }
      if constexpr (std::is_same_v<decltype(f(id)), bool>) {
        if (f(id)) {
          return true;
        }
      } else {
        f(id);
      }
    }
    return false;
  }
  // Whether any alive triple matches p (Jena's RuleContext.contains, used by noValue).
  [[nodiscard]] bool contains(const ValuePattern& p) const;
  // An upper bound of the candidates match() visits for p (the length of the index chain used).
  [[nodiscard]] std::size_t estimate(const ValuePattern& p) const;

  // Rebuilds the index chains without the erased triples when they make up a large share.
  // Must not run while a match() is in progress.
  void compact_if_worthwhile();
  [[nodiscard]] std::size_t memory_bytes() const;

 private:
  struct Rec {
    TermId s, p, o, vo;
  };
  struct Scan {
    TripleId first = kNoTriple;
    const std::vector<TripleId>* next = nullptr;  // the chain's links; nullptr: every id in order
    bool single = false;                          // an exact lookup: only `first`
  };
  static TripleId advance(const Scan& sc, TripleId id) {
    if (sc.single) {
      return kNoTriple;
    }
    return sc.next != nullptr ? (*sc.next)[id] : id + 1;
  }
  struct Indexes;

  [[nodiscard]] Scan scan(const ValuePattern& p) const;
  void link(TripleId id);

  const Dictionary& dict_;
  std::vector<Rec> recs_;
  std::vector<std::uint8_t> flags_;
  std::unique_ptr<Indexes> ix_;
  std::size_t alive_ = 0;
  std::size_t dead_linked_ = 0;  // erased triples still threaded through the chains
};

}  // namespace sf::knowledge
