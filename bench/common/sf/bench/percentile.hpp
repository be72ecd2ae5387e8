// Percentiles of measured samples, one definition for every benchmark: the nearest-rank method
// (the smallest sample with at least p of all samples at or below it), so a percentile is
// always a sample that was measured.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

namespace sf::bench {

// The p-percentile (0 <= p <= 1) of samples sorted in ascending order; T{} when there are none.
template <typename T>
T percentile_of_sorted(std::span<const T> sorted, double p) {
  if (sorted.empty()) {
    return T{};
  }
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

// The same of samples in any order.
template <typename T>
T percentile(std::vector<T> samples, double p) {
  std::sort(samples.begin(), samples.end());
  return percentile_of_sorted(std::span<const T>(samples), p);
}

}  // namespace sf::bench
