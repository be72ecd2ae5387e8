#include "sf/dds/executor.hpp"

#include <algorithm>
#include <thread>
#include <utility>

namespace sf::dds {

void Executor::post(Task task) {
  {
    const std::lock_guard lock{mutex_};
    tasks_.push_back(std::move(task));
    queued_.store(tasks_.size(), std::memory_order_release);
  }
  cv_.notify_one();
}

std::size_t Executor::run_pending() {
  std::deque<Task> batch;
  {
    const std::lock_guard lock{mutex_};
    batch.swap(tasks_);
    queued_.store(0, std::memory_order_release);
    notified_ = false;
  }
  for (auto& task : batch) {
    task();
  }
  return batch.size();
}

bool Executor::wait_for(std::chrono::nanoseconds timeout) {
  if (spin_.count() > 0) {
    const auto end = std::chrono::steady_clock::now() + std::min(spin_, timeout);
    while (queued_.load(std::memory_order_acquire) == 0 && std::chrono::steady_clock::now() < end) {
      std::this_thread::yield();  // let the DDS receive thread of this process run
    }
    if (queued_.load(std::memory_order_acquire) > 0) {
      return true;
    }
  }
  // Bounded so that "forever" does not overflow the condition variable's clock.
  timeout = std::min(timeout, std::chrono::nanoseconds{std::chrono::hours{24}});
  std::unique_lock lock{mutex_};
  cv_.wait_for(lock, timeout, [this] { return !tasks_.empty() || notified_; });
  notified_ = false;
  return !tasks_.empty();
}

void Executor::notify() {
  {
    const std::lock_guard lock{mutex_};
    notified_ = true;
  }
  cv_.notify_all();
}

std::size_t Executor::pending() const {
  const std::lock_guard lock{mutex_};
  return tasks_.size();
}

}  // namespace sf::dds
