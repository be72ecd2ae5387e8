#include "sf/ethercat/master/cyclic_runner.hpp"

#include "sf/core/realtime.hpp"

namespace sf::ethercat::master {

Status CyclicRunner::start(Callback on_cycle) {
  if (running_.exchange(true)) {
    return make_error(Errc::state, "cyclic thread already running");
  }
  stop_ = false;
  on_cycle_ = std::move(on_cycle);
  started_ = false;
  thread_ = std::thread([this] { loop(); });
  if (options_.realtime) {
    realtime_active_ = try_realtime(thread_, options_.priority);
  }
  return {};
}

void CyclicRunner::stop() {
  stop_ = true;
  if (thread_.joinable()) {
    thread_.join();
  }
  running_ = false;
}

void CyclicRunner::loop() {
  while (!stop_.load()) {
    cycle(on_cycle_);
  }
}

void CyclicRunner::run_cycles(std::size_t n, const Callback& on_cycle) {
  for (std::size_t i = 0; i < n; ++i) {
    cycle(on_cycle);
  }
}

void CyclicRunner::cycle(const Callback& on_cycle) {
  auto& clock = master_.clock();
  if (!started_) {
    deadline_ = clock.now();
    started_ = true;
  }
  deadline_ += options_.period;
  clock.sleep_until(deadline_);
  const auto woke = clock.now();
  std::lock_guard lock(master_.bus().mutex());
  master_.statistics().jitter.record(woke >= deadline_ ? woke - deadline_ : deadline_ - woke);
  const auto result = master_.exchange();
  if (options_.maintain) {
    master_.maintain();
  }
  if (on_cycle) {
    on_cycle(master_, result);
  }
  // After an overrun, skip the missed deadlines instead of rushing through
  // them (the slaves' watchdogs are the safety net, not catch-up cycles).
  const auto now = clock.now();
  if (now > deadline_ + options_.period) {
    const auto missed = (now - deadline_) / options_.period;
    deadline_ += missed * options_.period;
  }
}

CycleStatistics CyclicRunner::statistics() const {
  std::lock_guard lock(master_.bus().mutex());
  return master_.statistics();
}

}  // namespace sf::ethercat::master
