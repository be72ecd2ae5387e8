// The gateway's writer thread: samples and events from every server connection are queued here
// and written to the (store-and-forward) historian in batches, so that a slow or absent database
// never holds up the OPC UA side, and forwarding of buffered data runs on the same thread.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <span>
#include <thread>

#include "sf/historian/buffered_store.hpp"

namespace sf::cloud::detail {

struct WriterStats {
  std::uint64_t samples_received = 0;
  std::uint64_t samples_written = 0;  // accepted by the store (database or buffer)
  std::uint64_t samples_failed = 0;   // refused (logged): the buffer could not take them
  std::uint64_t events_written = 0;
  std::size_t queued = 0;
};

class SampleWriter {
 public:
  // Called on the writer thread after each batch the store accepted.
  using Committed = std::function<void(std::span<const historian::Sample>)>;

  SampleWriter(historian::BufferedStore& store, std::size_t batch, std::chrono::milliseconds flush_interval,
               Committed on_committed = nullptr);
  ~SampleWriter();
  SampleWriter(const SampleWriter&) = delete;
  SampleWriter& operator=(const SampleWriter&) = delete;

  void push(historian::Sample sample);  // any thread
  void push(historian::Event event);
  // Writes what is queued, then ends the thread. Idempotent.
  void stop();
  [[nodiscard]] WriterStats stats() const;

 private:
  void run();
  void write_batch(std::unique_lock<std::mutex>& lock);

  historian::BufferedStore& store_;
  std::size_t batch_;
  std::chrono::milliseconds flush_interval_;
  Committed on_committed_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<historian::Sample> samples_;
  std::deque<historian::Event> events_;
  WriterStats stats_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace sf::cloud::detail
