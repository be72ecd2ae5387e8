// CyclicRunner: runs a master's cycle on absolute deadlines (Clock::
// sleep_until, so cycles do not drift), in its own thread — SCHED_FIFO and
// mlockall when the process may, silently plain otherwise — or step by step
// in the caller's thread for deterministic tests with a ManualClock.
// Each cycle: wait for the deadline, exchange(), maintain(), the callback.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

#include "sf/core/result.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/master/statistics.hpp"

namespace sf::ethercat::master {

struct CyclicOptions {
  std::chrono::nanoseconds period{std::chrono::milliseconds{1}};
  bool realtime = true;  // try SCHED_FIFO + mlockall
  int priority = 80;     // SCHED_FIFO priority
  bool maintain = true;  // run diagnosis/recovery after each cycle
};

class CyclicRunner {
 public:
  // Called after every cycle, with the bus lock held: the place to read
  // inputs and write outputs of the process image.
  using Callback = std::function<void(Master&, const ExchangeResult&)>;

  explicit CyclicRunner(Master& master, CyclicOptions options = {}) : master_(master), options_(options) {}
  ~CyclicRunner() { stop(); }
  CyclicRunner(const CyclicRunner&) = delete;
  CyclicRunner& operator=(const CyclicRunner&) = delete;

  // Starts the cyclic thread; an error if it already runs.
  Status start(Callback on_cycle = {});
  // Stops after the current cycle and joins the thread.
  void stop();
  [[nodiscard]] bool running() const { return running_.load(); }
  // Whether the thread got SCHED_FIFO (false without the privilege).
  [[nodiscard]] bool realtime_active() const { return realtime_active_.load(); }

  // Runs n cycles in the calling thread (the same code as the thread).
  void run_cycles(std::size_t n, const Callback& on_cycle = {});

  // A copy of the master's statistics, taken under the bus lock.
  [[nodiscard]] CycleStatistics statistics() const;

 private:
  void loop();
  void cycle(const Callback& on_cycle);

  Master& master_;
  CyclicOptions options_;
  Callback on_cycle_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_{false};
  std::atomic<bool> realtime_active_{false};
  Clock::time_point deadline_{};
  bool started_ = false;
};

}  // namespace sf::ethercat::master
