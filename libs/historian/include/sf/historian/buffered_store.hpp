// Store-and-forward: a Store decorator that keeps writes the database cannot
// take right now in a durable local buffer (segment_log.hpp) and forwards
// them, in their original order, when it can again. The cloud gateway writes
// to a BufferedStore and calls poll() from its loop; nothing else changes.
//
//   writes  register_series, append, append_events: straight to the database
//           while it answers and nothing is buffered; otherwise into the
//           buffer (so a later write never overtakes an earlier one). They
//           fail only if the buffer itself cannot write (disk full, limit) or
//           the database refuses the data (a caller error, never buffered).
//   reads   go to the database; while it is away they fail with Errc::io.
//   poll()  when the back-off allows, forwards buffered records in batches.
//           Records the database refuses (not a connection problem) go to
//           rejected.log in the buffer directory instead of blocking the rest.
//
// Nothing is lost or duplicated: the buffer survives crashes (fdatasync per
// write), the cursor moves only after the database confirmed a batch, and a
// batch re-sent after a crash is a no-op thanks to the stores' idempotent keys.
// Thread-safe: one mutex serialises callers and poll().
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "sf/core/clock.hpp"
#include "sf/historian/segment_log.hpp"
#include "sf/historian/store.hpp"

namespace sf::historian {

struct BufferOptions {
  std::filesystem::path directory{};
  std::size_t segment_bytes = 8U << 20U;
  bool fsync = true;
  OnCorruption on_corruption = OnCorruption::salvage;
  // Refuse new writes (Errc::limit_exceeded) once this much is buffered.
  std::uint64_t max_buffered_bytes = 1ULL << 30U;
  // Back-off between attempts to reach the database: doubles up to the max.
  Clock::duration initial_backoff = std::chrono::milliseconds{200};
  Clock::duration max_backoff = std::chrono::seconds{30};
  // Forwarding: samples per database transaction, and per poll() call (so a
  // long backlog does not hold writers off for long).
  std::size_t forward_batch = 10'000;
  std::size_t forward_per_poll = 50'000;
};

struct BufferStats {
  bool database_up = false;
  std::uint64_t buffered_records = 0;
  std::uint64_t buffered_bytes = 0;
  std::uint64_t samples_buffered = 0;   // since open: samples that went into the buffer
  std::uint64_t samples_forwarded = 0;  // since open: buffered samples the database confirmed
  std::uint64_t records_rejected = 0;   // since open: records moved to rejected.log
  std::string last_error{};             // why the database was last given up on
  LogReport recovery{};                 // what opening the buffer found
};

class BufferedStore final : public Store {
 public:
  // Opens the database (and reopens it after failures) when needed.
  using Factory = std::function<Result<std::unique_ptr<Store>>()>;

  // Opening succeeds while the database is away (writes are buffered); it
  // fails only if the buffer cannot be opened.
  static Result<std::unique_ptr<BufferedStore>> open(Factory factory, BufferOptions options, Clock& clock);
  static Result<std::unique_ptr<BufferedStore>> open(std::string url, BufferOptions options, Clock& clock);

  Result<SeriesId> register_series(const SeriesInfo& info) override;
  Result<std::vector<Series>> list_series() override;
  Status append(std::span<const Sample> samples) override;
  Status append_events(std::span<const Event> events) override;
  Result<std::vector<Sample>> read_raw(SeriesId series, Timestamp from, Timestamp to,
                                       std::size_t limit) override;
  Result<std::optional<Sample>> latest(SeriesId series) override;
  Result<std::vector<AggregateRow>> aggregate(SeriesId series, Timestamp from, Timestamp to, Micros interval,
                                              Aggregate which) override;
  Result<std::vector<Event>> read_events(const EventQuery& query) override;
  Result<RetentionResult> apply_retention(Timestamp before) override;
  Result<int> schema_version() override;
  [[nodiscard]] std::string_view backend() const override { return "buffered"; }

  // Forwards buffered records if the back-off allows (up to forward_per_poll
  // samples). Returns the error that stopped forwarding, if any.
  Status poll();
  // Forwards everything now, ignoring the back-off; fails if the database is
  // still away (the records stay buffered).
  Status flush();
  [[nodiscard]] BufferStats stats() const;

 private:
  BufferedStore(Factory factory, BufferOptions options, Clock& clock, std::unique_ptr<SegmentLog> log);

  // The database if it is (or can now be) open and not backing off.
  Store* database(bool ignore_backoff);
  void database_failed(const Error& error);
  void database_ok();
  Status buffer(RecordType type, const Bytes& payload, std::uint64_t samples);
  // Writes straight to the database when nothing is buffered. The result when
  // it is final (done, or refused as the caller's mistake); nullopt when the
  // write must go to the buffer.
  template <typename R, typename F>
  std::optional<R> write_through(F&& write);
  // Forwards one batch; false when nothing is left. Errors: the database failed.
  Result<bool> forward_batch(std::uint64_t& samples_sent);
  // Decodes and writes records of one type; returns the samples written.
  Result<std::uint64_t> send(Store& db, std::span<const LogRecord> group);
  Status forward(std::uint64_t limit);
  template <typename F>
  auto with_database(F&& f) -> decltype(f(std::declval<Store&>()));

  Factory factory_;
  BufferOptions options_;
  Clock& clock_;
  std::unique_ptr<SegmentLog> log_;
  std::unique_ptr<Store> db_;
  Clock::time_point next_attempt_{};
  Clock::duration backoff_;
  BufferStats stats_;
  // Series this process registered, to register again in a database that
  // lost them (restored from an older backup) before their samples arrive.
  std::unordered_map<SeriesId, SeriesInfo> registered_;
  mutable std::mutex mutex_;
};

}  // namespace sf::historian
