#include "sample_writer.hpp"

#include <vector>

#include "sf/core/log.hpp"

namespace sf::cloud::detail {

SampleWriter::SampleWriter(historian::BufferedStore& store, std::size_t batch,
                           std::chrono::milliseconds flush_interval, Committed on_committed)
    : store_(store), batch_(batch), flush_interval_(flush_interval), on_committed_(std::move(on_committed)) {
  thread_ = std::thread([this] { run(); });
}

SampleWriter::~SampleWriter() {
  stop();
}

void SampleWriter::push(historian::Sample sample) {
  std::lock_guard lock(mutex_);
  samples_.push_back(std::move(sample));
  ++stats_.samples_received;
  if (samples_.size() >= batch_) {
    wake_.notify_one();
  }
}

void SampleWriter::push(historian::Event event) {
  std::lock_guard lock(mutex_);
  events_.push_back(std::move(event));
  wake_.notify_one();
}

void SampleWriter::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !thread_.joinable()) {
      return;
    }
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) {
    thread_.join();
  }
}

WriterStats SampleWriter::stats() const {
  std::lock_guard lock(mutex_);
  WriterStats s = stats_;
  s.queued = samples_.size();
  return s;
}

// A batch leaves when it is full or its oldest sample has waited flush_interval; between
// batches the buffered backlog is forwarded (BufferedStore::poll keeps its own back-off).
void SampleWriter::run() {
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait_for(lock, flush_interval_, [this] { return stopping_ || samples_.size() >= batch_; });
    while (!samples_.empty() || !events_.empty()) {
      write_batch(lock);
      if (samples_.size() < batch_ && !stopping_) {
        break;
      }
    }
    if (stopping_ && samples_.empty() && events_.empty()) {
      break;
    }
    lock.unlock();
    (void)store_.poll();
    lock.lock();
  }
  lock.unlock();
  // Leave what can be forwarded now in the database rather than in the buffer.
  (void)store_.poll();
}

// A backlog (the database slower than the servers) leaves in larger transactions, up to
// kBacklogBatches batches: a transaction's cost is mostly the index pages it rewrites, about one
// per series whatever the rows, so larger ones catch up where batch-sized ones fall further behind
// (bench_cloud_latency). Without a backlog a batch is what the settings say.
constexpr std::size_t kBacklogBatches = 16;

void SampleWriter::write_batch(std::unique_lock<std::mutex>& lock) {
  const std::size_t n = std::min(batch_ * kBacklogBatches, samples_.size());
  std::vector<historian::Sample> samples(
      std::make_move_iterator(samples_.begin()),
      std::make_move_iterator(samples_.begin() + static_cast<std::ptrdiff_t>(n)));
  samples_.erase(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(n));
  std::vector<historian::Event> events(std::make_move_iterator(events_.begin()),
                                       std::make_move_iterator(events_.end()));
  events_.clear();
  lock.unlock();
  bool ok = true;
  if (!samples.empty()) {
    if (auto st = store_.append(samples); !st) {
      ok = false;
      log::get("cloud")->error("writing {} samples failed: {}", samples.size(), st.error().describe());
    } else if (on_committed_) {
      on_committed_(samples);
    }
  }
  std::size_t events_ok = 0;
  if (!events.empty()) {
    if (auto st = store_.append_events(events); !st) {
      log::get("cloud")->error("writing {} events failed: {}", events.size(), st.error().describe());
    } else {
      events_ok = events.size();
    }
  }
  lock.lock();
  (ok ? stats_.samples_written : stats_.samples_failed) += samples.size();
  stats_.events_written += events_ok;
}

}  // namespace sf::cloud::detail
