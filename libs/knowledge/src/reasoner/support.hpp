// Derivation records: for every derived triple the rule and the matched triples that produced
// it, and the reverse edges from a premise to the records that use it. They explain results and
// drive retraction (a derived triple is suspect when a premise of its record goes away).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "sf/knowledge/store.hpp"

namespace sf::knowledge::engine {

class Support {
 public:
  struct Record {
    TripleId triple = kNoTriple;  // kNoTriple once dropped
    std::uint32_t rule = 0;
    std::uint32_t offset = 0;  // into the premise pool
    std::uint32_t count = 0;
  };

  // Records (or replaces) the derivation of triple t; returns the record id.
  std::uint32_t set(TripleId t, std::uint32_t rule, std::span<const TripleId> premises);
  void drop(TripleId t);
  [[nodiscard]] const Record* record_of(TripleId t) const;
  [[nodiscard]] const Record& record(std::uint32_t id) const { return records_[id]; }
  [[nodiscard]] std::span<const TripleId> premises(const Record& r) const {
    return {premises_.data() + r.offset, r.count};
  }

  // Calls f(dependent triple) for every live record that uses premise p.
  template <typename F>
  void for_each_dependent(TripleId p, F&& f) const {
    if (p >= first_edge_.size()) {
      return;
    }
    for (std::uint32_t e = first_edge_[p]; e != 0; e = edges_[e - 1].next) {
      const Record& r = records_[edges_[e - 1].record];
      if (r.triple != kNoTriple) {
        f(r.triple);
      }
    }
  }

  void compact_if_worthwhile();
  [[nodiscard]] std::size_t memory_bytes() const;

 private:
  struct Edge {
    std::uint32_t record = 0;
    std::uint32_t next = 0;  // edge index + 1, 0 ends the chain
  };
  void add_edges(std::uint32_t record_id);

  std::vector<Record> records_;
  std::vector<TripleId> premises_;
  std::vector<std::uint32_t> record_of_;   // per triple: record id + 1, 0 for none
  std::vector<std::uint32_t> first_edge_;  // per triple: edge index + 1
  std::vector<Edge> edges_;
  std::size_t dropped_ = 0;
};

}  // namespace sf::knowledge::engine
