#include "sf/ethercat/master/statistics.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include <fmt/format.h>

namespace sf::ethercat::master {

std::size_t DurationHistogram::bucket_of(std::uint64_t v) {
  if (v < kSub) {
    return static_cast<std::size_t>(v);
  }
  const auto exponent = static_cast<unsigned>(std::bit_width(v)) - 1U;  // >= kSubBits
  if (exponent > kMaxExponent) {
    return kBuckets - 1;
  }
  const auto sub = (v >> (exponent - kSubBits)) & (kSub - 1U);
  return static_cast<std::size_t>(exponent - kSubBits + 1U) * kSub + static_cast<std::size_t>(sub);
}

std::uint64_t DurationHistogram::upper_edge(std::size_t bucket) {
  if (bucket < kSub) {
    return bucket;
  }
  const auto exponent = static_cast<unsigned>(bucket / kSub) + kSubBits - 1U;
  const auto sub = static_cast<std::uint64_t>(bucket % kSub);
  const auto width = std::uint64_t{1} << (exponent - kSubBits);
  return ((kSub + sub) << (exponent - kSubBits)) + width - 1U;
}

void DurationHistogram::record(std::chrono::nanoseconds d) {
  const auto v = static_cast<std::uint64_t>(std::max<std::int64_t>(d.count(), 0));
  ++buckets_[bucket_of(v)];
  ++count_;
  min_ = std::min(min_, v);
  max_ = std::max(max_, v);
}

void DurationHistogram::reset() {
  *this = DurationHistogram{};
}

std::chrono::nanoseconds DurationHistogram::min() const {
  return std::chrono::nanoseconds{count_ == 0 ? 0 : static_cast<std::int64_t>(min_)};
}

std::chrono::nanoseconds DurationHistogram::quantile(double q) const {
  if (count_ == 0) {
    return std::chrono::nanoseconds{0};
  }
  q = std::clamp(q, 0.0, 1.0);
  // Rank of the sample we want, 1-based.
  const auto rank =
      std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_))));
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    seen += buckets_[b];
    if (seen >= rank) {
      if (b == kBuckets - 1) {
        return max();  // the overflow bucket has no upper edge
      }
      const auto edge = std::clamp(upper_edge(b), min_, max_);
      return std::chrono::nanoseconds{static_cast<std::int64_t>(edge)};
    }
  }
  return max();
}

std::string CycleStatistics::summary() const {
  auto us = [](std::chrono::nanoseconds d) { return static_cast<double>(d.count()) / 1000.0; };
  return fmt::format(
      "cycles {} lost {} wkc-errors {} | rtt min/med/p99/max {:.1f}/{:.1f}/{:.1f}/{:.1f} us | "
      "jitter med/p99/max {:.1f}/{:.1f}/{:.1f} us",
      cycles, lost_frames, wkc_errors, us(round_trip.min()), us(round_trip.median()),
      us(round_trip.quantile(0.99)), us(round_trip.max()), us(jitter.median()), us(jitter.quantile(0.99)),
      us(jitter.max()));
}

}  // namespace sf::ethercat::master
