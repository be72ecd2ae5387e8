// Fuzzes the OPC UA binary decoders (OPC 10000-6 §5.2) with arbitrary bytes: decode_message and
// every built-in type's decoder must accept or reject without reading out of bounds, recursing
// without bound or allocating without bound; whatever they accept must re-encode, and the
// re-encoding must be a fixed point (decode → encode → decode → encode gives the same bytes).
#include <cstddef>
#include <cstdint>

#include "sf/opcua/encoding.hpp"

namespace {

using namespace sf::opcua;

void check(bool ok) {
  if (!ok) {
    __builtin_trap();
  }
}

DecodeOptions tight_limits() {
  DecodeOptions options;
  options.limits.max_string_length = 64;
  options.limits.max_array_length = 16;
  options.limits.max_depth = 8;
  return options;
}

template <typename T>
void fuzz_one(sf::ByteSpan input, const DecodeOptions& options) {
  sf::ByteReader reader(input);
  T value{};
  if (!decode(reader, value, options).ok()) {
    return;
  }
  auto first = encode(value);
  check(first.ok());
  auto again = decode<T>(*first, options);
  check(again.ok());
  auto second = encode(*again);
  check(second.ok() && *second == *first);
}

void fuzz_message(sf::ByteSpan input, const DecodeOptions& options) {
  auto message = decode_message(input, options);
  if (!message.ok()) {
    check(status_of(message.error()).is_bad());
    return;
  }
  auto first = encode_message(*message);
  check(first.ok());
  auto again = decode_message(*first, options);
  check(again.ok() && again->index() == message->index());
  auto second = encode_message(*again);
  check(second.ok() && *second == *first);
  (void)to_string(*again);
}

template <typename... T>
void fuzz_all(sf::ByteSpan input, const DecodeOptions& options) {
  (fuzz_one<T>(input, options), ...);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sf::ByteSpan input(data, size);
  static const DecodeOptions defaults;
  static const DecodeOptions tight = tight_limits();
  for (const DecodeOptions* options : {&defaults, &tight}) {
    fuzz_message(input, *options);
    fuzz_all<bool, std::int8_t, std::uint8_t, std::int16_t, std::uint16_t, std::int32_t, std::uint32_t,
             std::int64_t, std::uint64_t, float, double, String, DateTime, Guid, ByteString, XmlElement,
             NodeId, ExpandedNodeId, StatusCode, QualifiedName, LocalizedText, ExtensionObject, DataValue,
             Variant, DiagnosticInfo>(input, *options);
  }
  return 0;
}
