#include "sf/core/clock.hpp"

#include <cerrno>
#include <ctime>

namespace sf {

Clock::time_point SteadyClock::now() const {
  return std::chrono::steady_clock::now();
}

Clock::utc_time SteadyClock::utc_now() const {
  return std::chrono::system_clock::now();
}

void SteadyClock::sleep_until(time_point deadline) {
  // libstdc++'s steady_clock is CLOCK_MONOTONIC; sleeping to an absolute
  // deadline keeps a periodic loop free of accumulated drift.
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline.time_since_epoch()).count();
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

SteadyClock& SteadyClock::instance() {
  static SteadyClock clock;
  return clock;
}

ScaledClock::ScaledClock(double factor)
    : factor_(factor > 0.0 ? factor : 1.0),
      origin_(std::chrono::steady_clock::now()),
      utc_origin_(std::chrono::system_clock::now()) {}

Clock::time_point ScaledClock::now() const {
  const auto real = std::chrono::steady_clock::now() - origin_;
  return origin_ + std::chrono::duration_cast<duration>(real * factor_);
}

Clock::utc_time ScaledClock::utc_now() const {
  const auto scaled = now() - origin_;
  return utc_origin_ + std::chrono::duration_cast<utc_time::duration>(scaled);
}

void ScaledClock::sleep_until(time_point deadline) {
  const auto ahead = deadline - now();
  if (ahead <= duration::zero()) {
    return;
  }
  SteadyClock::instance().sleep_until(std::chrono::steady_clock::now() +
                                      std::chrono::duration_cast<duration>(ahead / factor_));
}

Clock::time_point ManualClock::now() const {
  return time_point{std::chrono::nanoseconds{ns_.load(std::memory_order_acquire)}};
}

Clock::utc_time ManualClock::utc_now() const {
  return utc_start_ + std::chrono::duration_cast<utc_time::duration>(
                          std::chrono::nanoseconds{ns_.load(std::memory_order_acquire)});
}

void ManualClock::sleep_until(time_point deadline) {
  const auto target =
      std::chrono::duration_cast<std::chrono::nanoseconds>(deadline.time_since_epoch()).count();
  auto current = ns_.load(std::memory_order_acquire);
  while (current < target && !ns_.compare_exchange_weak(current, target, std::memory_order_acq_rel)) {
  }
}

void ManualClock::advance(duration d) {
  ns_.fetch_add(d.count(), std::memory_order_acq_rel);
}

void ManualClock::set(time_point t) {
  ns_.store(std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count(),
            std::memory_order_release);
}

}  // namespace sf
