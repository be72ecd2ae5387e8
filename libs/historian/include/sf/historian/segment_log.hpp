// The durable local buffer of store-and-forward: an append-only log of
// records in numbered segment files, plus a cursor file saying how far the
// database has confirmed.
//
// Why our own log and not a local SQLite file: the buffer must keep working
// exactly when a database is failing, possibly SQLite itself on the same disk
// (locked, or its library returning I/O errors); an append is one write() of
// one framed record plus fdatasync, with no page cache, locking or journal to
// go wrong; a torn write after a crash only ever affects the last record of
// the last segment; and a damaged file can be read past (every record carries
// a magic number and a CRC-32C), so corruption costs the damaged bytes only.
//
// Layout of DIR:
//   seg-<20-digit number>.log  header "SFHBLOG1" + u64 number, then records:
//                              u32 magic "SFR1" | u32 length | u32 crc32c(type, payload) | u8 type | payload
//   cursor                     u32 magic "SFHC" | u32 version | u64 segment | u64 offset | u32 crc32c
//   rejected.log               records the database refused (same framing)
//   corrupt/                   damaged bytes found in segments, kept for inspection
//   lock                       flock()ed while a process has the log open
//
// Delivery is at-least-once: the cursor moves after the database confirmed a
// batch, so a crash in between re-sends that batch, and the stores' idempotent
// writes (see store.hpp) turn the re-send into a no-op. For the same reason
// the cursor is replaced atomically but not synced.
#pragma once

#include <compare>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/historian/buffer_records.hpp"

namespace sf::historian {

inline constexpr std::size_t kSegmentHeaderBytes = 16;
inline constexpr std::size_t kRecordHeaderBytes = 13;
inline constexpr std::uint32_t kMaxRecordBytes = 64U << 20U;

// CRC-32C (Castagnoli), reflected, as in iSCSI and ext4.
std::uint32_t crc32c(ByteSpan data, std::uint32_t crc = 0);

Bytes segment_header(std::uint64_t number);
Bytes frame_record(RecordType type, ByteSpan payload);

// --- Parsing (pure functions over bytes; fuzzed by historian_buffer_fuzz) ------

struct RecordView {
  RecordType type{};
  std::size_t offset = 0;  // of the record header
  std::size_t end = 0;     // just past the payload
  [[nodiscard]] ByteSpan payload(ByteSpan file) const {
    return file.subspan(offset + kRecordHeaderBytes, end - offset - kRecordHeaderBytes);
  }
};

struct BadRegion {
  std::size_t offset = 0;
  std::size_t length = 0;
  std::string reason{};
};

struct SegmentScan {
  std::string header_error;         // not empty: not a segment file, nothing was read
  std::uint64_t number = 0;         // from the header
  std::vector<RecordView> records;  // readable records, in file order
  std::vector<BadRegion> bad;       // damaged bytes with readable records after them
  std::size_t valid_end = 0;        // just past the last readable record
  std::size_t tail_bytes = 0;       // bytes after valid_end that hold no whole record
};

// Reads the records of a segment image from `from` (a record boundary; the
// first one when 0). A damaged record is skipped by searching for the next
// magic number whose record checks out; what is in between is `bad`.
SegmentScan scan_segment(ByteSpan file, std::size_t from = 0);

// --- The log -------------------------------------------------------------------

struct LogPosition {
  std::uint64_t segment = 0;
  std::uint64_t offset = 0;
  // clang-tidy 14 reads the defaulted <=> as a comparison with literal 0.
  auto operator<=>(const LogPosition&) const = default;  // NOLINT(modernize-use-nullptr)
};

struct LogRecord {
  RecordType type{};
  Bytes payload{};
  LogPosition at{};
  LogPosition next{};  // where the record after it starts
};

enum class OnCorruption {
  salvage,  // keep every readable record, move damaged bytes to corrupt/, log an error
  fail,     // refuse to open (Errc::malformed), change nothing
};

struct SegmentLogOptions {
  std::filesystem::path directory{};
  std::size_t segment_bytes = 8U << 20U;  // a new segment starts beyond this size
  bool fsync = true;                      // fdatasync every append (survives power loss too)
  OnCorruption on_corruption = OnCorruption::salvage;
};

// What open() found and did about damage.
struct LogReport {
  std::uint64_t bad_regions = 0;
  std::uint64_t bad_bytes = 0;
  std::uint64_t torn_bytes = 0;  // an incomplete last record (a crash mid-append), cut off
  bool cursor_lost = false;      // cursor unreadable: replay from the oldest segment
  std::vector<std::string> messages{};
};

class SegmentLog {
 public:
  static Result<std::unique_ptr<SegmentLog>> open(SegmentLogOptions options);
  ~SegmentLog();
  SegmentLog(const SegmentLog&) = delete;
  SegmentLog& operator=(const SegmentLog&) = delete;

  // Durable when it returns (with fsync on); on failure nothing is appended.
  Status append(RecordType type, ByteSpan payload);
  // The oldest unconsumed records, in order: at least one if any, then more
  // while their payloads stay within max_bytes.
  Result<std::vector<LogRecord>> peek(std::size_t max_bytes);
  // `records` (a prefix of the last peek) are delivered: moves and persists
  // the cursor and deletes segments left wholly behind it.
  Status consume(std::span<const LogRecord> records);
  // Keeps records the database refused in rejected.log (then consume them).
  Status reject(std::span<const LogRecord> records) const;

  [[nodiscard]] bool empty() const { return pending_records_ == 0; }
  [[nodiscard]] std::uint64_t pending_records() const { return pending_records_; }
  [[nodiscard]] std::uint64_t pending_bytes() const { return pending_bytes_; }
  [[nodiscard]] const LogReport& report() const { return report_; }
  [[nodiscard]] const std::filesystem::path& directory() const { return options_.directory; }

 private:
  struct Loaded;
  explicit SegmentLog(SegmentLogOptions options);

  Status recover();
  Status recover_segment(std::uint64_t number, bool last);
  Status start_segment(std::uint64_t number);
  Status rotate();
  Status load(std::uint64_t number);
  Status save_cursor() const;
  void note_bad(std::uint64_t segment, ByteSpan file, const BadRegion& bad);
  [[nodiscard]] std::filesystem::path segment_path(std::uint64_t number) const;

  SegmentLogOptions options_;
  int lock_fd_ = -1;
  int active_fd_ = -1;
  std::uint64_t active_ = 0;             // segment appended to
  std::uint64_t active_size_ = 0;        // its length
  std::vector<std::uint64_t> segments_;  // existing segment numbers, ascending
  LogPosition cursor_;
  std::uint64_t pending_records_ = 0;
  std::uint64_t pending_bytes_ = 0;
  std::unique_ptr<Loaded> loaded_;  // the segment being read
  LogReport report_;
};

}  // namespace sf::historian
