// Clock: the seam through which every module reads time, so tests can drive
// timeouts, watchdogs, subscriptions and drift deterministically.
#pragma once

#include <atomic>
#include <chrono>
#include <optional>

namespace sf {

class Clock {
 public:
  using duration = std::chrono::nanoseconds;
  // Monotonic time; only differences are meaningful.
  using time_point = std::chrono::steady_clock::time_point;
  // Wall-clock (UTC) time, for timestamps that leave the process.
  using utc_time = std::chrono::system_clock::time_point;

  virtual ~Clock() = default;
  [[nodiscard]] virtual time_point now() const = 0;
  [[nodiscard]] virtual utc_time utc_now() const = 0;
  // Blocks (or, for a manual clock, advances) until now() >= deadline.
  virtual void sleep_until(time_point deadline) = 0;
};

// The real clock: std::chrono::steady_clock, sleeps with absolute deadlines
// (clock_nanosleep TIMER_ABSTIME on CLOCK_MONOTONIC) so cycles do not drift.
class SteadyClock final : public Clock {
 public:
  [[nodiscard]] time_point now() const override;
  [[nodiscard]] utc_time utc_now() const override;
  void sleep_until(time_point deadline) override;

  static SteadyClock& instance();
};

// Real time sped up (or slowed down) by a constant factor from the moment
// of construction: a simulation that should run N times faster than the
// wall clock while still driven by real sleeps. UTC advances at the same pace.
class ScaledClock final : public Clock {
 public:
  explicit ScaledClock(double factor);

  [[nodiscard]] time_point now() const override;
  [[nodiscard]] utc_time utc_now() const override;
  void sleep_until(time_point deadline) override;
  [[nodiscard]] double factor() const { return factor_; }

 private:
  double factor_;
  std::chrono::steady_clock::time_point origin_;
  utc_time utc_origin_;
};

// A clock that moves only when told to. sleep_until() jumps forward to the
// deadline, so code that sleeps in a loop runs instantly and repeatably.
// Thread-safe: now() may be read while another thread advances the clock.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(utc_time utc_start = utc_time{std::chrono::seconds{1'700'000'000}})
      : utc_start_(utc_start) {}

  [[nodiscard]] time_point now() const override;
  [[nodiscard]] utc_time utc_now() const override;
  void sleep_until(time_point deadline) override;

  void advance(duration d);
  void set(time_point t);

 private:
  std::atomic<std::int64_t> ns_{0};
  utc_time utc_start_;
};

// The earlier of two optional deadlines (nothing when neither is set).
[[nodiscard]] inline std::optional<Clock::time_point> earliest(std::optional<Clock::time_point> a,
                                                               std::optional<Clock::time_point> b) {
  if (!a) {
    return b;
  }
  return b && *b < *a ? b : a;
}

}  // namespace sf
