// Framing and parsing of buffer segments (see segment_log.hpp).
#include <array>
#include <cstring>

#include <fmt/format.h>

#include "sf/historian/segment_log.hpp"

namespace sf::historian {

namespace {

constexpr std::string_view kSegmentMagic = "SFHBLOG1";
constexpr std::uint32_t kRecordMagic = 0x31524653;  // "SFR1" little-endian

constexpr std::array<std::uint32_t, 256> make_crc_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) {
      c = (c & 1U) != 0 ? (c >> 1U) ^ 0x82F63B78U : c >> 1U;  // reversed Castagnoli polynomial
    }
    table[i] = c;
  }
  return table;
}
constexpr auto kCrcTable = make_crc_table();

std::uint32_t record_crc(RecordType type, ByteSpan payload) {
  const auto t = static_cast<std::uint8_t>(type);
  return crc32c(payload, crc32c(ByteSpan{&t, 1}));
}

bool known_type(std::uint8_t t) {
  return t >= static_cast<std::uint8_t>(RecordType::series) &&
         t <= static_cast<std::uint8_t>(RecordType::events);
}

// The record at `pos`, or why there is none.
Result<RecordView> record_at(ByteSpan file, std::size_t pos) {
  if (file.size() - pos < kRecordHeaderBytes) {
    return make_error(Errc::malformed, "incomplete record header");
  }
  const auto* p = file.data() + pos;
  if (load_le<std::uint32_t>(p) != kRecordMagic) {
    return make_error(Errc::malformed, "no record magic");
  }
  const auto length = load_le<std::uint32_t>(p + 4);
  if (length > kMaxRecordBytes) {
    return make_error(Errc::malformed, fmt::format("record length {} over the limit", length));
  }
  if (file.size() - pos - kRecordHeaderBytes < length) {
    return make_error(Errc::malformed, fmt::format("record length {} past the end of the file", length));
  }
  const auto type = p[12];
  if (!known_type(type)) {
    return make_error(Errc::malformed, fmt::format("unknown record type {}", type));
  }
  RecordView view{static_cast<RecordType>(type), pos, pos + kRecordHeaderBytes + length};
  if (record_crc(view.type, view.payload(file)) != load_le<std::uint32_t>(p + 8)) {
    return make_error(Errc::malformed, "record checksum mismatch");
  }
  return view;
}

// The first offset after `pos` where a whole, intact record starts.
std::size_t next_record(ByteSpan file, std::size_t pos) {
  std::uint8_t magic[4];
  store_le(magic, kRecordMagic);
  for (std::size_t p = pos; p + kRecordHeaderBytes <= file.size(); ++p) {
    const auto* hit = static_cast<const std::uint8_t*>(
        std::memchr(file.data() + p, magic[0], file.size() - p - kRecordHeaderBytes + 1));
    if (hit == nullptr) {
      break;
    }
    p = static_cast<std::size_t>(hit - file.data());
    if (std::memcmp(hit, magic, 4) == 0 && record_at(file, p).ok()) {
      return p;
    }
  }
  return file.size();
}

}  // namespace

std::uint32_t crc32c(ByteSpan data, std::uint32_t crc) {
  std::uint32_t c = ~crc;
  for (const auto b : data) {
    c = kCrcTable[(c ^ b) & 0xffU] ^ (c >> 8U);
  }
  return ~c;
}

Bytes segment_header(std::uint64_t number) {
  Bytes out(kSegmentHeaderBytes);
  std::memcpy(out.data(), kSegmentMagic.data(), kSegmentMagic.size());
  store_le(out.data() + 8, number);
  return out;
}

Bytes frame_record(RecordType type, ByteSpan payload) {
  Bytes out;
  out.reserve(kRecordHeaderBytes + payload.size());
  ByteWriter w(out);
  w.u32(kRecordMagic);
  w.u32(static_cast<std::uint32_t>(payload.size()));
  w.u32(record_crc(type, payload));
  w.u8(static_cast<std::uint8_t>(type));
  w.bytes(payload);
  return out;
}

SegmentScan scan_segment(ByteSpan file, std::size_t from) {
  SegmentScan out;
  if (file.size() < kSegmentHeaderBytes ||
      std::memcmp(file.data(), kSegmentMagic.data(), kSegmentMagic.size()) != 0) {
    out.header_error = "not a buffer segment (no SFHBLOG1 header)";
    return out;
  }
  out.number = load_le<std::uint64_t>(file.data() + 8);
  std::size_t pos = std::max(from, kSegmentHeaderBytes);
  out.valid_end = std::min(pos, file.size());
  while (pos < file.size()) {
    auto record = record_at(file, pos);
    if (record) {
      out.records.push_back(*record);
      pos = record->end;
      out.valid_end = pos;
      continue;
    }
    const auto next = next_record(file, pos + 1);
    if (next >= file.size()) {
      out.tail_bytes = file.size() - pos;
      break;
    }
    out.bad.push_back(BadRegion{pos, next - pos, record.error().message});
    pos = next;
  }
  return out;
}

}  // namespace sf::historian
