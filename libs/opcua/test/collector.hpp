// Collects values delivered on other threads (client callbacks) and waits for them.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <utility>
#include <vector>

namespace sf::opcua::test {

// Values delivered on another thread, waited for with a condition variable.
template <typename T>
class Collector {
 public:
  void add(T value) {
    {
      std::lock_guard lock(mutex_);
      values_.push_back(std::move(value));
    }
    cv_.notify_all();
  }
  // True once at least n values arrived (false after timeout).
  bool wait_for(std::size_t n, std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return values_.size() >= n; });
  }
  // True once pred(values) holds (false after timeout).
  template <typename Pred>
  bool wait_until(Pred pred, std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return pred(values_); });
  }
  std::vector<T> values() {
    std::lock_guard lock(mutex_);
    return values_;
  }
  std::size_t size() {
    std::lock_guard lock(mutex_);
    return values_.size();
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<T> values_;
};

}  // namespace sf::opcua::test
