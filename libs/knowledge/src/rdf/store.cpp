#include "sf/knowledge/store.hpp"

#include <algorithm>

#include "flat_map.hpp"

namespace sf::knowledge {
namespace {

using detail::FlatMap;
using detail::U64Traits;

struct Chain {
  TripleId first = kNoTriple;
  TripleId last = kNoTriple;
  std::uint32_t count = 0;
};

struct SpoKey {
  TermId s = kNoTerm;
  TermId p = kNoTerm;
  TermId o = kNoTerm;
  bool operator==(const SpoKey&) const = default;
};

struct SpoTraits {
  static constexpr SpoKey empty() { return SpoKey{}; }
  static std::size_t hash(const SpoKey& k) {
    return static_cast<std::size_t>(
        detail::mix64((std::uint64_t{k.s} << 32 | k.p) ^ (std::uint64_t{k.o} * 0x9e3779b97f4a7c15ULL)));
  }
};

std::uint64_t pair_key(TermId a, TermId b) {
  return std::uint64_t{a} << 32 | b;
}

using ChainMap = FlatMap<std::uint64_t, Chain, U64Traits>;

}  // namespace

// One chain map and one link array per index; the order of kinds is the order of `chains`.
struct TripleStore::Indexes {
  enum Kind : std::size_t { kPs, kPo, kP, kS, kO, kCount };
  ChainMap chains[kCount];
  std::vector<TripleId> next[kCount];
  FlatMap<SpoKey, TripleId, SpoTraits> spo;

  static std::uint64_t key(Kind k, TermId s, TermId p, TermId vo) {
    switch (k) {
      case kPs:
        return pair_key(p, s);
      case kPo:
        return pair_key(p, vo);
      case kP:
        return p;
      case kS:
        return s;
      case kO:
        return vo;
      case kCount:
        break;
    }
    return 0;
  }
};

TripleStore::TripleStore(const Dictionary& dict) : dict_(dict), ix_(std::make_unique<Indexes>()) {}

TripleStore::~TripleStore() = default;

std::pair<TripleId, bool> TripleStore::insert(const Triple& t) {
  const TermId vo = dict_.value_id(t.o);
  bool inserted = false;
  TripleId& slot = ix_->spo.get_or_insert(SpoKey{t.s, t.p, vo}, inserted);
  if (!inserted) {
    return {slot, false};
  }
  const auto id = static_cast<TripleId>(recs_.size());
  slot = id;
  recs_.push_back(Rec{t.s, t.p, t.o, vo});
  flags_.push_back(kAlive);
  for (auto& n : ix_->next) {
    n.push_back(kNoTriple);
  }
  link(id);
  ++alive_;
  return {id, true};
}

TripleId TripleStore::find(const Triple& t) const {
  const TripleId* id = ix_->spo.find(SpoKey{t.s, t.p, dict_.value_id(t.o)});
  return id == nullptr ? kNoTriple : *id;
}

void TripleStore::erase(TripleId id) {
  if (!alive(id)) {
    return;
  }
  const Rec& r = recs_[id];
  ix_->spo.erase(SpoKey{r.s, r.p, r.vo});
  flags_[id] = 0;
  --alive_;
  ++dead_linked_;
  for (std::size_t k = 0; k < Indexes::kCount; ++k) {
    if (Chain* c = ix_->chains[k].find(Indexes::key(static_cast<Indexes::Kind>(k), r.s, r.p, r.vo))) {
      --c->count;
    }
  }
}

void TripleStore::link(TripleId id) {
  const Rec& r = recs_[id];
  for (std::size_t k = 0; k < Indexes::kCount; ++k) {
    bool inserted = false;
    Chain& c =
        ix_->chains[k].get_or_insert(Indexes::key(static_cast<Indexes::Kind>(k), r.s, r.p, r.vo), inserted);
    if (inserted) {
      c.first = id;
    } else {
      ix_->next[k][c.last] = id;
    }
    c.last = id;
    ++c.count;
  }
}

TripleStore::Scan TripleStore::scan(const ValuePattern& p) const {
  if (p.s != kNoTerm && p.p != kNoTerm && p.o != kNoTerm) {
    const TripleId* id = ix_->spo.find(SpoKey{p.s, p.p, p.o});
    return Scan{id == nullptr ? kNoTriple : *id, nullptr, true};
  }
  using K = Indexes::Kind;
  // Candidate indexes for the bound positions; the shortest chain wins.
  K kinds[2];
  std::size_t n = 0;
  if (p.p != kNoTerm) {
    if (p.s != kNoTerm) {
      kinds[n++] = K::kPs;
    }
    if (p.o != kNoTerm) {
      kinds[n++] = K::kPo;
    }
    if (n == 0) {
      kinds[n++] = K::kP;
    }
  } else {
    if (p.s != kNoTerm) {
      kinds[n++] = K::kS;
    }
    if (p.o != kNoTerm) {
      kinds[n++] = K::kO;
    }
  }
  if (n == 0) {
    return Scan{recs_.empty() ? kNoTriple : 0, nullptr, false};
  }
  const Chain* best = nullptr;
  K best_kind = kinds[0];
  for (std::size_t i = 0; i < n; ++i) {
    const Chain* c = ix_->chains[kinds[i]].find(Indexes::key(kinds[i], p.s, p.p, p.o));
    if (c == nullptr) {
      return Scan{};
    }
    if (best == nullptr || c->count < best->count) {
      best = c;
      best_kind = kinds[i];
    }
  }
  return Scan{best->first, &ix_->next[best_kind], false};
}

bool TripleStore::contains(const ValuePattern& p) const {
  const Scan sc = scan(p);
  const auto end = static_cast<TripleId>(recs_.size());
  for (TripleId id = sc.first; id != kNoTriple && id < end; id = advance(sc, id)) {
    const Rec& r = recs_[id];
    if ((flags_[id] & kAlive) != 0 && (p.s == kNoTerm || r.s == p.s) && (p.p == kNoTerm || r.p == p.p) &&
        (p.o == kNoTerm || r.vo == p.o)) {
      return true;
    }
  }
  return false;
}

std::size_t TripleStore::estimate(const ValuePattern& p) const {
  if (p.s != kNoTerm && p.p != kNoTerm && p.o != kNoTerm) {
    return 1;
  }
  using K = Indexes::Kind;
  std::size_t best = alive_;
  auto consider = [&](K k) {
    const Chain* c = ix_->chains[k].find(Indexes::key(k, p.s, p.p, p.o));
    best = std::min<std::size_t>(best, c == nullptr ? 0 : c->count);
  };
  if (p.p != kNoTerm) {
    if (p.s != kNoTerm) {
      consider(K::kPs);
    }
    if (p.o != kNoTerm) {
      consider(K::kPo);
    }
    if (p.s == kNoTerm && p.o == kNoTerm) {
      consider(K::kP);
    }
  } else {
    if (p.s != kNoTerm) {
      consider(K::kS);
    }
    if (p.o != kNoTerm) {
      consider(K::kO);
    }
  }
  return best;
}

void TripleStore::compact_if_worthwhile() {
  if (dead_linked_ < 4096 || dead_linked_ < alive_ / 2) {
    return;
  }
  for (std::size_t k = 0; k < Indexes::kCount; ++k) {
    ix_->chains[k].clear();
    std::fill(ix_->next[k].begin(), ix_->next[k].end(), kNoTriple);
  }
  for (TripleId id = 0; id < recs_.size(); ++id) {
    if (alive(id)) {
      link(id);
    }
  }
  dead_linked_ = 0;
}

std::size_t TripleStore::memory_bytes() const {
  std::size_t bytes = recs_.capacity() * sizeof(Rec) + flags_.capacity() + ix_->spo.memory_bytes();
  for (std::size_t k = 0; k < Indexes::kCount; ++k) {
    bytes += ix_->chains[k].memory_bytes() + ix_->next[k].capacity() * sizeof(TripleId);
  }
  return bytes;
}

}  // namespace sf::knowledge
