// The store-and-forward buffer's parsers on arbitrary bytes: the segment
// scanner (as for a damaged file found after a crash) and the record payload
// decoders. Every record the scanner reports must lie inside the input, in
// order and without overlap, and every decoder must return (value or error).
#include <cstddef>
#include <cstdint>

#include "sf/historian/buffer_records.hpp"
#include "sf/historian/segment_log.hpp"

namespace {

void decode(sf::historian::RecordType type, sf::ByteSpan payload) {
  using sf::historian::RecordType;
  switch (type) {
    case RecordType::series:
      (void)sf::historian::decode_series(payload);
      break;
    case RecordType::samples:
      (void)sf::historian::decode_samples(payload);
      break;
    case RecordType::events:
      (void)sf::historian::decode_events(payload);
      break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sf::ByteSpan input{data, size};
  const auto scan = sf::historian::scan_segment(input);
  std::size_t end = sf::historian::kSegmentHeaderBytes;
  for (const auto& r : scan.records) {
    if (r.offset < end || r.end > size || r.end < r.offset + sf::historian::kRecordHeaderBytes) {
      __builtin_trap();
    }
    end = r.end;
    decode(r.type, r.payload(input));
  }
  for (const auto& bad : scan.bad) {
    if (bad.offset + bad.length > size) {
      __builtin_trap();
    }
  }
  // The same bytes as a payload of each kind.
  decode(sf::historian::RecordType::series, input);
  decode(sf::historian::RecordType::samples, input);
  decode(sf::historian::RecordType::events, input);
  return 0;
}
