// The payloads of store-and-forward buffer records (see segment_log.hpp for
// the framing): a series registration, a batch of samples or of events.
// Little-endian, each payload starting with a format version byte; decoding
// is bounds-checked and never trusts a count or length it reads.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"

namespace sf::historian {

enum class RecordType : std::uint8_t { series = 1, samples = 2, events = 3 };

Bytes encode_series(const SeriesInfo& info);
Bytes encode_samples(std::span<const Sample> samples);
Bytes encode_events(std::span<const Event> events);

Result<SeriesInfo> decode_series(ByteSpan payload);
Result<std::vector<Sample>> decode_samples(ByteSpan payload);
Result<std::vector<Event>> decode_events(ByteSpan payload);

}  // namespace sf::historian
