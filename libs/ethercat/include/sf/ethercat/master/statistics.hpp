// Cycle statistics of the master: counters and two cheap histograms (round
// trip, cycle jitter). Recording is a few integer operations on a fixed array:
// no allocation, no lock, so it can run in the cyclic thread every cycle.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <string>

namespace sf::ethercat::master {

// Log-linear histogram of durations: exact below 16 ns, then 16 buckets per
// power of two (relative error below 1/16), up to 2^41 ns (~36 min).
class DurationHistogram {
 public:
  void record(std::chrono::nanoseconds d);
  void reset();

  [[nodiscard]] std::uint64_t count() const { return count_; }
  [[nodiscard]] std::chrono::nanoseconds min() const;
  [[nodiscard]] std::chrono::nanoseconds max() const { return std::chrono::nanoseconds{max_}; }
  // The q-quantile (0 <= q <= 1), as the upper edge of its bucket clamped to
  // [min, max]; 0 when nothing was recorded.
  [[nodiscard]] std::chrono::nanoseconds quantile(double q) const;
  [[nodiscard]] std::chrono::nanoseconds median() const { return quantile(0.5); }

 private:
  static constexpr unsigned kSubBits = 4;
  static constexpr unsigned kSub = 1U << kSubBits;
  static constexpr unsigned kMaxExponent = 40;
  static constexpr std::size_t kBuckets = std::size_t{kMaxExponent - kSubBits + 2} * kSub;

  static std::size_t bucket_of(std::uint64_t v);
  static std::uint64_t upper_edge(std::size_t bucket);

  std::array<std::uint64_t, kBuckets> buckets_{};
  std::uint64_t count_ = 0;
  std::uint64_t min_ = UINT64_MAX;
  std::uint64_t max_ = 0;
};

struct CycleStatistics {
  std::uint64_t cycles = 0;       // exchange() calls
  std::uint64_t lost_frames = 0;  // cyclic frames that did not come back
  std::uint64_t wkc_errors = 0;   // frames that came back with an unexpected WKC
  DurationHistogram round_trip;   // send → matching receive
  DurationHistogram jitter;       // |cycle start − its deadline| (cyclic thread only)

  void reset() { *this = CycleStatistics{}; }
  // "cycles 10000 lost 3 wkc-errors 0 rtt min/med/p99/max 12/15/40/80 us jitter ..."
  [[nodiscard]] std::string summary() const;
};

}  // namespace sf::ethercat::master
