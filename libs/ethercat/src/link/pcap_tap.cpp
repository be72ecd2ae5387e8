// PcapTap and read_pcap: the classic libpcap file format (pcap-savefile(5)):
// a 24-byte global header (magic 0xA1B2C3D4 for microsecond, 0xA1B23C4D for
// nanosecond timestamps; version 2.4; snaplen; link type 1 = Ethernet), then
// per frame a 16-byte record header (seconds, sub-second, captured length,
// original length) and the frame bytes. We write little-endian; readers
// recognise byte order by the magic.
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/ethercat/link.hpp"

namespace sf::ethercat {
namespace {

constexpr std::uint32_t kMagicMicro = 0xA1B2C3D4;
constexpr std::uint32_t kMagicNano = 0xA1B23C4D;
constexpr std::uint32_t kLinktypeEthernet = 1;
constexpr std::uint32_t kSnaplen = 65535;
constexpr std::size_t kGlobalHeaderSize = 24;
constexpr std::size_t kRecordHeaderSize = 16;
// Far above any Ethernet frame; a larger record length means a corrupt file.
constexpr std::uint32_t kMaxRecordSize = 262144;

Status write_all(std::FILE* f, ByteSpan bytes, const std::filesystem::path& file) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) {
    return make_error(Errc::io,
                      fmt::format("writing pcap file '{}': {}", file.string(), std::strerror(errno)));
  }
  return {};
}

std::uint32_t swap32(std::uint32_t v) {
  return ((v & 0xFFU) << 24U) | ((v & 0xFF00U) << 8U) | ((v >> 8U) & 0xFF00U) | (v >> 24U);
}

}  // namespace

Result<std::unique_ptr<PcapTap>> PcapTap::open(std::unique_ptr<Link> inner, const std::filesystem::path& file,
                                               const Clock& clock, PcapResolution resolution) {
  if (!inner) {
    return make_error(Errc::invalid_argument, "PcapTap needs a link to wrap");
  }
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (f == nullptr) {
    return make_error(Errc::io,
                      fmt::format("cannot create pcap file '{}': {}", file.string(), std::strerror(errno)));
  }
  std::array<std::uint8_t, kGlobalHeaderSize> header{};
  SpanWriter w(header);
  w.u32(resolution == PcapResolution::nanoseconds ? kMagicNano : kMagicMicro);
  w.u16(2);  // version 2.4
  w.u16(4);
  w.u32(0);  // thiszone: timestamps are UTC
  w.u32(0);  // sigfigs
  w.u32(kSnaplen);
  w.u32(kLinktypeEthernet);
  const Status written = write_all(f, header, file);
  if (!written || std::fflush(f) != 0) {
    std::fclose(f);
    return written ? make_error(Errc::io, fmt::format("flushing pcap file '{}'", file.string()))
                   : written.error();
  }
  return std::unique_ptr<PcapTap>(new PcapTap(std::move(inner), f, clock, resolution));
}

PcapTap::~PcapTap() {
  if (file_ != nullptr) {
    std::fclose(file_);
  }
}

Status PcapTap::record(ByteSpan frame) {
  const auto since_epoch =
      std::chrono::duration_cast<std::chrono::nanoseconds>(clock_->utc_now().time_since_epoch());
  const auto ns = static_cast<std::uint64_t>(std::max<std::int64_t>(since_epoch.count(), 0));
  const std::uint64_t sub = ns % 1'000'000'000U;
  std::array<std::uint8_t, kRecordHeaderSize> header{};
  SpanWriter w(header);
  w.u32(static_cast<std::uint32_t>(ns / 1'000'000'000U));
  w.u32(static_cast<std::uint32_t>(resolution_ == PcapResolution::nanoseconds ? sub : sub / 1000U));
  w.u32(static_cast<std::uint32_t>(frame.size()));
  w.u32(static_cast<std::uint32_t>(frame.size()));
  const std::lock_guard lock(mutex_);
  if (fwrite(header.data(), 1, header.size(), file_) != header.size() ||
      fwrite(frame.data(), 1, frame.size(), file_) != frame.size() || std::fflush(file_) != 0) {
    return make_error(Errc::io,
                      fmt::format("pcap tap on {}: write failed: {}", inner_->name(), std::strerror(errno)));
  }
  ++frames_written_;
  return {};
}

Status PcapTap::send(ByteSpan frame) {
  SF_TRY(inner_->send(frame));
  if (auto s = record(frame); !s) {
    // The frame left; a failing capture must not fail the link.
    log::get("ethercat")->warn("{}", s.error().describe());
  }
  return {};
}

Result<std::size_t> PcapTap::receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) {
  auto n = inner_->receive(buf, timeout);
  if (n && *n > 0) {
    if (auto s = record(buf.first(*n)); !s) {
      log::get("ethercat")->warn("{}", s.error().describe());
    }
  }
  return n;
}

Result<PcapFile> read_pcap(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    return make_error(Errc::io, fmt::format("cannot open pcap file '{}'", file.string()));
  }
  const Bytes bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (bytes.size() < kGlobalHeaderSize) {
    return make_error(Errc::malformed, fmt::format("pcap file '{}' is shorter than the {}-byte header",
                                                   file.string(), kGlobalHeaderSize));
  }
  ByteReader r(bytes);
  std::uint32_t magic = r.u32();
  const bool swapped = magic == swap32(kMagicMicro) || magic == swap32(kMagicNano);
  auto u32 = [&] { return swapped ? swap32(r.u32()) : r.u32(); };
  magic = swapped ? swap32(magic) : magic;
  if (!r.ok() || (magic != kMagicMicro && magic != kMagicNano)) {
    return make_error(Errc::malformed, fmt::format("'{}' is not a classic pcap file", file.string()));
  }
  PcapFile out;
  out.resolution = magic == kMagicNano ? PcapResolution::nanoseconds : PcapResolution::microseconds;
  r.skip(12);  // version, thiszone, sigfigs
  out.snaplen = u32();
  out.linktype = u32();
  if (!r.ok()) {
    return r.error(fmt::format("pcap file '{}' header", file.string()));
  }
  const std::uint64_t scale = out.resolution == PcapResolution::nanoseconds ? 1U : 1000U;
  while (!r.at_end()) {
    PcapRecord rec;
    const std::uint64_t secs = u32();
    const std::uint64_t sub = u32();
    const std::uint32_t captured = u32();
    rec.original_length = u32();
    if (r.ok() && captured > kMaxRecordSize) {
      return make_error(Errc::malformed, fmt::format("pcap file '{}': record {} claims {} bytes",
                                                     file.string(), out.records.size(), captured));
    }
    const ByteSpan data = r.bytes(captured);
    if (!r.ok()) {
      return r.error(fmt::format("pcap file '{}' record {}", file.string(), out.records.size()));
    }
    rec.data.assign(data.begin(), data.end());
    rec.timestamp = Clock::utc_time{std::chrono::duration_cast<Clock::utc_time::duration>(
        std::chrono::nanoseconds{static_cast<std::int64_t>(secs * 1'000'000'000U + sub * scale)})};
    out.records.push_back(std::move(rec));
  }
  return out;
}

}  // namespace sf::ethercat
