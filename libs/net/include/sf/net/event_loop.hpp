// EventLoop: a single-threaded reactor over Linux epoll. One thread runs it; every other thread
// talks to it through post(). Timers live in a min-heap whose earliest deadline bounds the
// epoll_wait timeout; an eventfd wakes the loop for posted work and stop().
//
// Timers read time from the Clock the loop was made with. With a ManualClock a timer runs on the
// loop's first pass after the clock reached its deadline: advance the clock, then post() anything
// to wake the loop (epoll_wait still sleeps in real time, bounded by what the clock says is left).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>

#include "sf/core/clock.hpp"

namespace sf::net {

class EventLoop {
 public:
  using TimerId = std::uint64_t;
  static constexpr unsigned kReadable = 1;
  static constexpr unsigned kWritable = 2;
  // Also reported to watchers (never requested): the peer hung up or the socket has an error.
  static constexpr unsigned kError = 4;

  explicit EventLoop(const Clock& clock = SteadyClock::instance());
  ~EventLoop();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  // Runs until stop(); the calling thread becomes the loop thread. Work posted before run()
  // runs first. May be called again after it returned.
  void run();
  // Any thread; run() returns after the callback that is running now.
  void stop();
  // Any thread; fn runs on the loop thread, in FIFO order with other posted work.
  void post(std::function<void()> fn);
  // True on the thread inside run() (and, before the first run(), on the constructing thread).
  [[nodiscard]] bool in_loop_thread() const;

  [[nodiscard]] const Clock& clock() const;

  // Loop thread. Runs fn once after delay (0 = on the next iteration).
  TimerId add_timer(std::chrono::nanoseconds delay, std::function<void()> fn);
  // Loop thread. Runs fn every period (first after one period) until cancelled.
  TimerId add_periodic(std::chrono::nanoseconds period, std::function<void()> fn);
  // Loop thread. Safe from inside any callback (including the timer's own); unknown ids are
  // ignored.
  void cancel_timer(TimerId id);

  // Loop thread. Level-triggered readiness callbacks for fd (kReadable | kWritable). The
  // callback gets the ready set, which may include kError. One watcher per fd.
  void watch(int fd, unsigned events, std::function<void(unsigned ready)> fn);
  void modify(int fd, unsigned events);
  // Safe from inside callbacks (also the fd's own); the callback is not called again.
  void unwatch(int fd);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// An EventLoop running on its own std::thread. The destructor stops and joins it.
class LoopThread {
 public:
  explicit LoopThread(const Clock& clock = SteadyClock::instance());
  ~LoopThread();
  LoopThread(const LoopThread&) = delete;
  LoopThread& operator=(const LoopThread&) = delete;

  EventLoop& loop() { return loop_; }
  // Runs fn on the loop thread and waits for it (for setup/teardown from other threads).
  // Called on the loop thread itself, runs fn directly.
  void run_sync(const std::function<void()>& fn);

 private:
  EventLoop loop_;
  std::thread thread_;
};

}  // namespace sf::net
