// Checks shared by both back ends: a series description is usable, and every
// sample of a batch refers to a registered series. The database enforces the
// latter with a foreign key too; checking first names the missing series in
// the error instead of failing the batch with a bare constraint message.
#pragma once

#include <functional>
#include <span>
#include <unordered_set>

#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"

namespace sf::historian::detail {

// server and node_id must be non-empty; data_type a known type.
Status validate(const SeriesInfo& info);

// The error for a key whose id is held by another key (see series_id()).
Error collision(const SeriesInfo& info, const SeriesInfo& existing);

class KnownSeries {
 public:
  using Lookup = std::function<Result<bool>(SeriesId)>;

  // Ids not seen before are looked up once (another process may have
  // registered them); unknown ones give Errc::not_found naming the id.
  Status check(std::span<const Sample> samples, const Lookup& lookup);
  void add(SeriesId id) { ids_.insert(id); }
  void clear() { ids_.clear(); }

 private:
  std::unordered_set<SeriesId> ids_;
};

}  // namespace sf::historian::detail
