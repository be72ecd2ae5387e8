// Executor: the application's work queue and its strand. Cyclone calls
// listeners on its own threads; they post() here. Application code never runs
// concurrently with itself:
//  - queued delivery (default): tasks wait in the queue until the application
//    thread drains it (run_pending), so handlers run only on that thread;
//  - inline delivery (set_inline): a listener thread that finds the strand
//    free and nothing queued runs the task at once, on that thread, holding
//    the strand. This saves the wake-up of the application thread per
//    message (tens of microseconds on a virtual machine), which dominates a
//    request/response exchange. The application thread takes the strand with
//    hold() for everything it does with the objects the tasks touch.
// A listener never blocks on the strand: when it is taken (by the
// application, by another listener thread, or by the task that caused the
// callback on the same thread, e.g. a write delivered locally), or tasks are
// queued already (order is kept), the task is queued for the application
// thread's next run_pending(). Never blocking matters: Cyclone waits for a
// listener in progress before it calls that listener again, so a listener
// blocked on the strand held by a thread that writes to its reader would
// deadlock. For the same reason a listener thread runs only its own task,
// never queued ones (they may write to the topic of the reader whose listener
// the thread is in).
// An inline task that writes blocks the receive thread for as long as the
// write does: Cyclone blocks a RELIABLE write (up to max_blocking_time) when
// the writer's unacknowledged data exceed its high-water mark, and the
// acknowledgements arrive on the receive thread; small messages (the Contract
// Net's) stay far below it.
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

  // Thread-safe; runs the task inline (see above) or queues it and wakes a
  // thread blocked in wait_for().
  void post(Task task);
  // Runs the tasks queued at the time of the call (tasks they post wait for
  // the next call), holding the strand. Returns how many ran.
  std::size_t run_pending();
  // Blocks until a task is queued, notify() is called or `timeout` passes
  // (real time: this waits for I/O). Returns true if tasks are queued.
  // Call without holding the strand, or inline tasks cannot run meanwhile.
  bool wait_for(std::chrono::nanoseconds timeout);
  // Wakes wait_for() without a task (e.g. to stop a loop).
  void notify();
  // wait_for() first polls for up to `spin` before it blocks: trades CPU for
  // the wake-up latency of a blocked thread. 0 (default): no spin.
  void set_spin(std::chrono::nanoseconds spin) { spin_ = spin; }
  // Inline delivery on or off (default off). Turn it on once the objects the
  // tasks touch exist, and from then on touch them only under hold(). Turned
  // off under hold(), no task runs inline after the call.
  void set_inline(bool on) { inline_.store(on, std::memory_order_release); }
  [[nodiscard]] bool is_inline() const { return inline_.load(std::memory_order_acquire); }
  // After tasks ran inline, the application thread is woken (notify()) if
  // `check` returns true; it runs under the strand. Without a check it is
  // always woken, which costs a thread wake-up per message: a check such as
  // "a timer is now due earlier than the thread sleeps" avoids that. Set it
  // under hold().
  void set_wake_check(std::function<bool()> check) { wake_check_ = std::move(check); }
  // The strand, held by the application thread: while held, no task runs on
  // another thread, and a post from this thread (e.g. a listener Cyclone calls
  // on the writing thread for a local reader) is queued, not run nested in
  // what the holder is doing. Recursive: run_pending() may run under it.
  class Hold {
   public:
    explicit Hold(std::recursive_mutex& strand);
    ~Hold() { unlock(); }
    Hold(const Hold&) = delete;
    Hold& operator=(const Hold&) = delete;
    void unlock();

   private:
    std::recursive_mutex* strand_;
  };
  [[nodiscard]] Hold hold() { return Hold{strand_}; }
  [[nodiscard]] std::size_t pending() const;

 private:
  [[nodiscard]] bool may_run_inline() const;
  void enqueue(Task task);
  // Runs `task` with the strand held, then the wake check.
  void run_inline(Task& task);
  std::size_t run_batch();

  std::recursive_mutex strand_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Task> tasks_;
  std::atomic<bool> notified_{false};   // written under mutex_; read without it while spinning
  std::atomic<std::size_t> queued_{0};  // tasks_.size(), readable without the lock while spinning
  std::atomic<bool> inline_{false};
  std::function<bool()> wake_check_;
  std::chrono::nanoseconds spin_{0};
};

}  // namespace sf::dds
