// Executor: the application's work queue. Cyclone calls listeners on its own
// threads; they only post() here, and the application drains the queue on its
// thread (run_pending), so application code never runs on Cyclone's threads
// and needs no locks of its own.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>

namespace sf::dds {

class Executor {
 public:
  using Task = std::function<void()>;

  // Thread-safe; wakes a thread blocked in wait_for().
  void post(Task task);
  // Runs the tasks queued at the time of the call (tasks they post wait for
  // the next call). Returns how many ran. Call from one thread at a time.
  std::size_t run_pending();
  // Blocks until a task is queued, notify() is called or `timeout` passes
  // (real time: this waits for I/O). Returns true if tasks are queued.
  bool wait_for(std::chrono::nanoseconds timeout);
  // Wakes wait_for() without a task (e.g. to stop a loop).
  void notify();
  // wait_for() first polls for up to `spin` before it blocks: trades CPU for
  // the wake-up latency of a blocked thread (tens of microseconds on a busy
  // host), which dominates a request/response exchange. 0 (default): no spin.
  void set_spin(std::chrono::nanoseconds spin) { spin_ = spin; }
  [[nodiscard]] std::size_t pending() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Task> tasks_;
  bool notified_ = false;
  std::atomic<std::size_t> queued_{0};  // tasks_.size(), readable without the lock while spinning
  std::chrono::nanoseconds spin_{0};
};

}  // namespace sf::dds
