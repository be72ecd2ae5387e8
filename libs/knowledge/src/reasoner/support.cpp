#include "support.hpp"

#include <algorithm>

namespace sf::knowledge::engine {

std::uint32_t Support::set(TripleId t, std::uint32_t rule, std::span<const TripleId> premises) {
  drop(t);
  const auto id = static_cast<std::uint32_t>(records_.size());
  records_.push_back(Record{t, rule, static_cast<std::uint32_t>(premises_.size()),
                            static_cast<std::uint32_t>(premises.size())});
  premises_.insert(premises_.end(), premises.begin(), premises.end());
  if (record_of_.size() <= t) {
    record_of_.resize(static_cast<std::size_t>(t) + 1, 0);
  }
  record_of_[t] = id + 1;
  add_edges(id);
  return id;
}

void Support::add_edges(std::uint32_t record_id) {
  const Record& r = records_[record_id];
  for (std::uint32_t i = 0; i < r.count; ++i) {
    const TripleId p = premises_[r.offset + i];
    if (std::find(premises_.begin() + r.offset, premises_.begin() + r.offset + i, p) !=
        premises_.begin() + r.offset + i) {
      continue;  // the same triple matched two patterns: one edge is enough
    }
    if (first_edge_.size() <= p) {
      first_edge_.resize(static_cast<std::size_t>(p) + 1, 0);
    }
    edges_.push_back(Edge{record_id, first_edge_[p]});
    first_edge_[p] = static_cast<std::uint32_t>(edges_.size());
  }
}

void Support::drop(TripleId t) {
  if (t < record_of_.size() && record_of_[t] != 0) {
    records_[record_of_[t] - 1].triple = kNoTriple;
    record_of_[t] = 0;
    ++dropped_;
  }
}

const Support::Record* Support::record_of(TripleId t) const {
  return t < record_of_.size() && record_of_[t] != 0 ? &records_[record_of_[t] - 1] : nullptr;
}

// Rebuilds records, premises and edges from the live records once most are dropped.
void Support::compact_if_worthwhile() {
  if (dropped_ < 4096 || dropped_ * 2 < records_.size()) {
    return;
  }
  std::vector<Record> old_records;
  std::vector<TripleId> old_premises;
  old_records.swap(records_);
  old_premises.swap(premises_);
  edges_.clear();
  std::fill(first_edge_.begin(), first_edge_.end(), 0);
  std::fill(record_of_.begin(), record_of_.end(), 0);
  dropped_ = 0;
  for (const Record& r : old_records) {
    if (r.triple != kNoTriple) {
      set(r.triple, r.rule, std::span<const TripleId>(old_premises.data() + r.offset, r.count));
    }
  }
}

std::size_t Support::memory_bytes() const {
  return records_.capacity() * sizeof(Record) + premises_.capacity() * sizeof(TripleId) +
         record_of_.capacity() * sizeof(std::uint32_t) + first_edge_.capacity() * sizeof(std::uint32_t) +
         edges_.capacity() * sizeof(Edge);
}

}  // namespace sf::knowledge::engine
