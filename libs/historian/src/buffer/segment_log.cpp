// The buffer's segment files, cursor and recovery (see segment_log.hpp).
#include "sf/historian/segment_log.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <set>

#include <fmt/format.h>

#include "sf/core/log.hpp"

namespace sf::historian {

namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t kCursorMagic = 0x43484653;  // "SFHC"
constexpr std::uint32_t kCursorVersion = 1;
constexpr std::size_t kCursorBytes = 28;

Error sys_error(std::string_view what, const fs::path& path) {
  // (not strerror: it is not thread-safe)
  return make_error(Errc::io,
                    fmt::format("{} {}: {}", what, path.string(), std::generic_category().message(errno)));
}

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  [[nodiscard]] int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_;
};

Status write_all(int fd, ByteSpan data, const fs::path& path) {
  while (!data.empty()) {
    const auto n = ::write(fd, data.data(), data.size());
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return sys_error("write", path);
    }
    data = data.subspan(static_cast<std::size_t>(n));
  }
  return {};
}

// Bytes [offset, offset + length) of a file; length 0 means to the end.
Result<Bytes> read_file(const fs::path& path, std::uint64_t offset = 0, std::uint64_t length = 0) {
  Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) {
    return sys_error("open", path);
  }
  if (length == 0) {
    const auto end = ::lseek(fd.get(), 0, SEEK_END);
    if (end < 0) {
      return sys_error("seek", path);
    }
    length = static_cast<std::uint64_t>(end) > offset ? static_cast<std::uint64_t>(end) - offset : 0;
  }
  Bytes out(length);
  std::size_t done = 0;
  while (done < out.size()) {
    const auto n = ::pread(fd.get(), out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n <= 0) {
      return n == 0 ? make_error(Errc::io, fmt::format("read {}: file shorter than expected", path.string()))
                    : sys_error("read", path);
    }
    done += static_cast<std::size_t>(n);
  }
  return out;
}

// Makes a rename or a new file in `dir` durable.
void sync_dir(const fs::path& dir) {
  Fd fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (fd.get() >= 0) {
    ::fsync(fd.get());
  }
}

// Writes a small file atomically: temporary file, fdatasync, rename.
Status replace_file(const fs::path& path, ByteSpan data, bool durable) {
  const auto tmp = fs::path{path.string() + ".tmp"};
  Fd fd(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (fd.get() < 0) {
    return sys_error("create", tmp);
  }
  SF_TRY(write_all(fd.get(), data, tmp));
  if (durable && ::fdatasync(fd.get()) != 0) {
    return sys_error("sync", tmp);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    return sys_error("rename", tmp);
  }
  if (durable) {
    sync_dir(path.parent_path());
  }
  return {};
}

std::optional<std::uint64_t> segment_number(const fs::path& file) {
  const auto name = file.filename().string();
  if (!name.starts_with("seg-") || !name.ends_with(".log") || name.size() != 4 + 20 + 4) {
    return std::nullopt;
  }
  std::uint64_t n = 0;
  for (const char c : name.substr(4, 20)) {
    if (c < '0' || c > '9') {
      return std::nullopt;
    }
    n = n * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return n;
}

std::optional<LogPosition> decode_cursor(ByteSpan data) {
  ByteReader r(data);
  const auto magic = r.u32();
  const auto version = r.u32();
  LogPosition pos{r.u64(), r.u64()};
  const auto crc = r.u32();
  if (!r.ok() || !r.at_end() || magic != kCursorMagic || version != kCursorVersion ||
      crc != crc32c(data.first(kCursorBytes - 4))) {
    return std::nullopt;
  }
  return pos;
}

}  // namespace

struct SegmentLog::Loaded {
  std::uint64_t number = 0;
  Bytes data;
  std::vector<RecordView> records;
  std::size_t scanned_to = 0;
};

SegmentLog::SegmentLog(SegmentLogOptions options) : options_(std::move(options)) {}

SegmentLog::~SegmentLog() {
  if (active_fd_ >= 0) {
    ::close(active_fd_);
  }
  if (lock_fd_ >= 0) {
    ::close(lock_fd_);  // releases the flock
  }
}

fs::path SegmentLog::segment_path(std::uint64_t number) const {
  return options_.directory / fmt::format("seg-{:020}.log", number);
}

Result<std::unique_ptr<SegmentLog>> SegmentLog::open(SegmentLogOptions options) {
  if (options.directory.empty()) {
    return make_error(Errc::invalid_argument, "store-and-forward buffer: no directory given");
  }
  std::error_code ec;
  fs::create_directories(options.directory, ec);
  if (ec) {
    return make_error(
        Errc::io, fmt::format("store-and-forward buffer {}: {}", options.directory.string(), ec.message()));
  }
  std::unique_ptr<SegmentLog> log{new SegmentLog(std::move(options))};
  const auto lock_path = log->options_.directory / "lock";
  log->lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (log->lock_fd_ < 0) {
    return sys_error("open", lock_path);
  }
  if (::flock(log->lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    return make_error(Errc::state, fmt::format("store-and-forward buffer {} is in use by another process",
                                               log->options_.directory.string()));
  }
  if (auto st = log->recover(); !st) {
    return st.error().with_context(
        fmt::format("store-and-forward buffer {}", log->options_.directory.string()));
  }
  return log;
}

Status SegmentLog::recover() {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(options_.directory, ec)) {
    if (const auto n = segment_number(entry.path())) {
      segments_.push_back(*n);
    }
  }
  if (ec) {
    return make_error(Errc::io, fmt::format("list {}: {}", options_.directory.string(), ec.message()));
  }
  std::sort(segments_.begin(), segments_.end());
  const auto cursor_path = options_.directory / "cursor";
  std::optional<LogPosition> cursor;
  if (fs::exists(cursor_path, ec)) {
    auto data = read_file(cursor_path);
    cursor = data ? decode_cursor(*data) : std::nullopt;
    if (!cursor) {
      report_.cursor_lost = true;
      report_.messages.push_back(
          "cursor file unreadable: replaying from the oldest segment (the database skips what it already "
          "has)");
      log::get("historian")
          ->warn("store-and-forward buffer {}: {}", options_.directory.string(), report_.messages.back());
    }
  }
  const std::uint64_t first = segments_.empty() ? 1 : segments_.front();
  cursor_ = cursor.value_or(LogPosition{first, kSegmentHeaderBytes});
  // Segments wholly behind the cursor were delivered; a crash kept them.
  while (!segments_.empty() && segments_.front() < cursor_.segment) {
    fs::remove(segment_path(segments_.front()), ec);
    segments_.erase(segments_.begin());
  }
  if (!segments_.empty() && segments_.front() > cursor_.segment) {
    cursor_ = LogPosition{segments_.front(), kSegmentHeaderBytes};
  }
  const auto existing = segments_;
  for (std::size_t i = 0; i < existing.size(); ++i) {
    SF_TRY(recover_segment(existing[i], i + 1 == existing.size()));
  }
  if (active_fd_ < 0) {
    SF_TRY(start_segment(
        std::max<std::uint64_t>(cursor_.segment, segments_.empty() ? 1 : segments_.back() + 1)));
    if (cursor_.segment != active_ || cursor_.offset > active_size_) {
      cursor_ = LogPosition{segments_.front(), kSegmentHeaderBytes};
    }
  }
  return save_cursor();
}

Status SegmentLog::recover_segment(std::uint64_t number, bool last) {
  const auto path = segment_path(number);
  auto data = read_file(path);
  if (!data) {
    return data.error();
  }
  const auto scan = scan_segment(*data);
  std::vector<BadRegion> bad = scan.bad;
  if (!scan.header_error.empty()) {
    bad.push_back(BadRegion{0, data->size(), scan.header_error});
  } else if (scan.tail_bytes > 0 && !last) {
    bad.push_back(BadRegion{scan.valid_end, scan.tail_bytes, "damaged end of a closed segment"});
  }
  if (!bad.empty() && options_.on_corruption == OnCorruption::fail) {
    return make_error(
        Errc::malformed,
        fmt::format("{} is damaged at byte {} ({}, {} bytes); {} readable records in it. Open with "
                    "on_corruption=salvage to forward them and keep the damaged bytes in corrupt/",
                    path.filename().string(), bad.front().offset, bad.front().reason, bad.front().length,
                    scan.records.size()));
  }
  for (const auto& region : bad) {
    note_bad(number, *data, region);
  }
  if (!scan.header_error.empty()) {
    std::error_code ec;
    fs::rename(path, options_.directory / "corrupt" / path.filename(), ec);
    if (ec) {
      return make_error(Errc::io, fmt::format("move {} aside: {}", path.string(), ec.message()));
    }
    segments_.erase(std::find(segments_.begin(), segments_.end(), number));
    return {};
  }
  for (const auto& r : scan.records) {
    if (LogPosition{number, r.offset} >= cursor_) {
      ++pending_records_;
      pending_bytes_ += r.end - r.offset - kRecordHeaderBytes;
    }
  }
  if (!last) {
    return {};
  }
  // The last segment is where a crash can leave half a record: cut it off.
  if (scan.tail_bytes > 0) {
    report_.torn_bytes += scan.tail_bytes;
    report_.messages.push_back(fmt::format("{}: cut off {} bytes of an incomplete last record",
                                           path.filename().string(), scan.tail_bytes));
    log::get("historian")
        ->warn("store-and-forward buffer {}: {}", options_.directory.string(), report_.messages.back());
  }
  active_fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (active_fd_ < 0 || ::ftruncate(active_fd_, static_cast<off_t>(scan.valid_end)) != 0) {
    return sys_error("open for append", path);
  }
  active_ = number;
  active_size_ = scan.valid_end;
  return {};
}

void SegmentLog::note_bad(std::uint64_t segment, ByteSpan file, const BadRegion& bad) {
  const auto name = fmt::format("seg-{:020}-at-{}.bin", segment, bad.offset);
  const auto dir = options_.directory / "corrupt";
  std::error_code ec;
  if (fs::exists(dir / name, ec)) {
    return;  // seen before (reading the segment again)
  }
  fs::create_directories(dir, ec);
  const auto keep = replace_file(dir / name, file.subspan(bad.offset, bad.length), options_.fsync);
  ++report_.bad_regions;
  report_.bad_bytes += bad.length;
  report_.messages.push_back(
      fmt::format("{}: {} damaged bytes at byte {} ({}){}; the readable records around "
                  "them are kept",
                  segment_path(segment).filename().string(), bad.length, bad.offset, bad.reason,
                  keep ? fmt::format(", copied to corrupt/{}", name) : ""));
  log::get("historian")
      ->error("store-and-forward buffer {}: {}", options_.directory.string(), report_.messages.back());
}

Status SegmentLog::start_segment(std::uint64_t number) {
  const auto path = segment_path(number);
  Fd fd(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644));
  if (fd.get() < 0) {
    return sys_error("create", path);
  }
  SF_TRY(write_all(fd.get(), segment_header(number), path));
  if (options_.fsync) {
    ::fdatasync(fd.get());
    sync_dir(options_.directory);
  }
  if (active_fd_ >= 0) {
    ::close(active_fd_);
  }
  active_fd_ = fd.release();
  active_ = number;
  active_size_ = kSegmentHeaderBytes;
  segments_.push_back(number);
  return {};
}

Status SegmentLog::rotate() {
  if (::fdatasync(active_fd_) != 0) {
    return sys_error("sync", segment_path(active_));
  }
  return start_segment(active_ + 1);
}

Status SegmentLog::append(RecordType type, ByteSpan payload) {
  if (payload.size() > kMaxRecordBytes) {
    return make_error(Errc::limit_exceeded, fmt::format("buffer record of {} bytes is over the {} byte limit",
                                                        payload.size(), kMaxRecordBytes));
  }
  if (active_size_ >= options_.segment_bytes && active_size_ > kSegmentHeaderBytes) {
    SF_TRY(rotate());
  }
  const auto frame = frame_record(type, payload);
  const auto path = segment_path(active_);
  auto st = write_all(active_fd_, frame, path);
  if (st && options_.fsync && ::fdatasync(active_fd_) != 0) {
    st = sys_error("sync", path);
  }
  if (!st) {
    // Leave no partial record behind a failed append (disk full).
    (void)::ftruncate(active_fd_, static_cast<off_t>(active_size_));
    return st;
  }
  active_size_ += frame.size();
  ++pending_records_;
  pending_bytes_ += payload.size();
  return {};
}

Status SegmentLog::load(std::uint64_t number) {
  const auto path = segment_path(number);
  if (!loaded_ || loaded_->number != number) {
    auto data = read_file(path, 0, number == active_ ? active_size_ : 0);
    if (!data) {
      return data.error();
    }
    loaded_ = std::make_unique<Loaded>();
    loaded_->number = number;
    loaded_->data = std::move(*data);
  } else if (number == active_ && loaded_->data.size() < active_size_) {
    // The segment being appended to has grown since: read only what is new.
    auto more = read_file(path, loaded_->data.size(), active_size_ - loaded_->data.size());
    if (!more) {
      return more.error();
    }
    loaded_->data.insert(loaded_->data.end(), more->begin(), more->end());
  } else {
    return {};
  }
  const auto scan = scan_segment(loaded_->data, loaded_->scanned_to);
  for (const auto& bad : scan.bad) {
    note_bad(number, loaded_->data, bad);
  }
  loaded_->records.insert(loaded_->records.end(), scan.records.begin(), scan.records.end());
  loaded_->scanned_to = scan.valid_end;
  return {};
}

Result<std::vector<LogRecord>> SegmentLog::peek(std::size_t max_bytes) {
  std::vector<LogRecord> out;
  std::size_t total = 0;
  LogPosition pos = cursor_;
  for (;;) {
    SF_TRY(load(pos.segment));
    const auto& recs = loaded_->records;
    auto it = std::lower_bound(recs.begin(), recs.end(), pos.offset,
                               [](const RecordView& r, std::uint64_t off) { return r.offset < off; });
    for (; it != recs.end(); ++it) {
      const auto payload = it->payload(loaded_->data);
      if (!out.empty() && total + payload.size() > max_bytes) {
        return out;
      }
      out.push_back(LogRecord{it->type,
                              Bytes{payload.begin(), payload.end()},
                              {pos.segment, it->offset},
                              {pos.segment, it->end}});
      total += payload.size();
    }
    const auto next = std::upper_bound(segments_.begin(), segments_.end(), pos.segment);
    if (next == segments_.end()) {
      break;
    }
    pos = LogPosition{*next, kSegmentHeaderBytes};
  }
  if (out.size() != pending_records_) {
    // Every record was read: what the files hold now is the truth (a segment
    // replaced or damaged behind our back).
    log::get("historian")
        ->error("store-and-forward buffer {}: {} records pending, {} readable", options_.directory.string(),
                pending_records_, out.size());
    pending_records_ = out.size();
    pending_bytes_ = total;
  }
  return out;
}

Status SegmentLog::consume(std::span<const LogRecord> records) {
  if (records.empty()) {
    return {};
  }
  for (const auto& r : records) {
    --pending_records_;
    pending_bytes_ -= r.payload.size();
  }
  cursor_ = records.back().next;
  // At the end of a closed segment the cursor moves on to the next one, so
  // the closed one can go.
  while (cursor_.segment < active_ && loaded_ && loaded_->number == cursor_.segment &&
         (loaded_->records.empty() || loaded_->records.back().offset < cursor_.offset)) {
    const auto next = std::upper_bound(segments_.begin(), segments_.end(), cursor_.segment);
    cursor_ = LogPosition{next == segments_.end() ? active_ : *next, kSegmentHeaderBytes};
  }
  SF_TRY(save_cursor());
  while (!segments_.empty() && segments_.front() < cursor_.segment) {
    std::error_code ec;
    fs::remove(segment_path(segments_.front()), ec);
    segments_.erase(segments_.begin());
  }
  return {};
}

Status SegmentLog::save_cursor() const {
  Bytes data;
  ByteWriter w(data);
  w.u32(kCursorMagic);
  w.u32(kCursorVersion);
  w.u64(cursor_.segment);
  w.u64(cursor_.offset);
  w.u32(crc32c(data));
  // Atomic (rename) but not synced: a cursor that falls back after a power
  // cut only re-sends batches the database then skips (idempotent keys);
  // syncing it would cost three fsyncs per forwarded batch.
  return replace_file(options_.directory / "cursor", data, false);
}

Status SegmentLog::reject(std::span<const LogRecord> records) const {
  const auto path = options_.directory / "rejected.log";
  std::error_code ec;
  const bool fresh = !fs::exists(path, ec);
  Fd fd(::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644));
  if (fd.get() < 0) {
    return sys_error("open", path);
  }
  if (fresh) {
    SF_TRY(write_all(fd.get(), segment_header(0), path));
  }
  for (const auto& r : records) {
    SF_TRY(write_all(fd.get(), frame_record(r.type, r.payload), path));
  }
  if (options_.fsync && ::fdatasync(fd.get()) != 0) {
    return sys_error("sync", path);
  }
  return {};
}

}  // namespace sf::historian
