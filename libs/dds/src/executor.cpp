#include "sf/dds/executor.hpp"

#include <algorithm>
#include <thread>
#include <utility>

namespace sf::dds {
namespace {

// Tasks running, or strands held, on this thread (any executor): a post from
// inside is queued, never run nested inside it.
thread_local int running_tasks = 0;

struct Running {
  Running() { ++running_tasks; }
  ~Running() { --running_tasks; }
  Running(const Running&) = delete;
  Running& operator=(const Running&) = delete;
};

}  // namespace

Executor::Hold::Hold(std::recursive_mutex& strand) : strand_(&strand) {
  strand_->lock();
  ++running_tasks;
}

void Executor::Hold::unlock() {
  if (strand_ != nullptr) {
    --running_tasks;
    strand_->unlock();
    strand_ = nullptr;
  }
}

bool Executor::may_run_inline() const {
  // Queued tasks go first: a task may not overtake an older one (e.g. a
  // reader's liveliness change its last data sample).
  return running_tasks == 0 && inline_.load(std::memory_order_acquire) &&
         queued_.load(std::memory_order_acquire) == 0;
}

void Executor::post(Task task) {
  if (may_run_inline()) {
    std::unique_lock strand{strand_, std::try_to_lock};
    // Checked again under the strand: set_inline(false) under hold() means no
    // task runs inline once it returns, and the queue may have filled.
    if (strand.owns_lock() && may_run_inline()) {
      run_inline(task);
      return;
    }
  }
  enqueue(std::move(task));
}

void Executor::enqueue(Task task) {
  {
    const std::lock_guard lock{mutex_};
    tasks_.push_back(std::move(task));
    queued_.store(tasks_.size(), std::memory_order_release);
  }
  cv_.notify_one();
}

void Executor::run_inline(Task& task) {
  {
    const Running running;
    task();
  }
  // What the task queued (a local delivery of its writes) is left to the
  // application thread, which enqueue() woke: run here, still inside the
  // listener of the reader that called us, such a task could write to that
  // reader's topic, and Cyclone would wait for this very listener to return.
  //
  // The application thread sleeps until its next timer as it knew it before
  // the task; the task may have set an earlier one.
  if (!wake_check_ || wake_check_()) {
    notify();
  }
}

std::size_t Executor::run_pending() {
  const std::lock_guard strand{strand_};
  return run_batch();
}

std::size_t Executor::run_batch() {
  std::deque<Task> batch;
  {
    const std::lock_guard lock{mutex_};
    batch.swap(tasks_);
    queued_.store(0, std::memory_order_release);
    notified_.store(false, std::memory_order_release);
  }
  const Running running;
  for (auto& task : batch) {
    task();
  }
  return batch.size();
}

bool Executor::wait_for(std::chrono::nanoseconds timeout) {
  if (spin_.count() > 0) {
    const auto end = std::chrono::steady_clock::now() + std::min(spin_, timeout);
    while (queued_.load(std::memory_order_acquire) == 0 && !notified_.load(std::memory_order_acquire) &&
           std::chrono::steady_clock::now() < end) {
      std::this_thread::yield();  // let the DDS receive thread of this process run
    }
    if (queued_.load(std::memory_order_acquire) > 0) {
      return true;
    }
  }
  // Bounded so that "forever" does not overflow the condition variable's clock.
  timeout = std::min(timeout, std::chrono::nanoseconds{std::chrono::hours{24}});
  std::unique_lock lock{mutex_};
  cv_.wait_for(lock, timeout,
               [this] { return !tasks_.empty() || notified_.load(std::memory_order_acquire); });
  notified_.store(false, std::memory_order_release);
  return !tasks_.empty();
}

void Executor::notify() {
  {
    const std::lock_guard lock{mutex_};
    notified_.store(true, std::memory_order_release);
  }
  cv_.notify_all();
}

std::size_t Executor::pending() const {
  const std::lock_guard lock{mutex_};
  return tasks_.size();
}

}  // namespace sf::dds
