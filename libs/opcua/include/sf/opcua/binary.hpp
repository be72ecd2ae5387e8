// OPC UA Binary encoding (OPC 10000-6 §5.2) of the built-in types, enumerations and arrays,
// and the whole-value entry points encode()/decode(). Encoder and Decoder (codec.hpp) carry
// limits, depth and errors; extension_registry.hpp turns ExtensionObject bodies into typed
// structures.
//
// Decoding is safe on hostile input: every length is checked against the bytes that remain and
// against DecodeLimits before anything is allocated, nesting is bounded, and the first error is
// kept with its StatusCode (BadDecodingError, BadEncodingLimitsExceeded, ...), the byte offset
// and the field path.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/codec.hpp"
#include "sf/opcua/containers.hpp"
#include "sf/opcua/extension_registry.hpp"
#include "sf/opcua/status_code.hpp"
#include "sf/opcua/variant.hpp"

namespace sf::opcua {

// ---- Built-in types (OPC 10000-6 §5.2.2) ----------------------------------------------------

inline void encode_binary(Encoder& e, bool v) {
  e.writer().u8(v ? 1 : 0);
}
inline void encode_binary(Encoder& e, std::int8_t v) {
  e.writer().i8(v);
}
inline void encode_binary(Encoder& e, std::uint8_t v) {
  e.writer().u8(v);
}
inline void encode_binary(Encoder& e, std::int16_t v) {
  e.writer().write(v);
}
inline void encode_binary(Encoder& e, std::uint16_t v) {
  e.writer().u16(v);
}
inline void encode_binary(Encoder& e, std::int32_t v) {
  e.writer().i32(v);
}
inline void encode_binary(Encoder& e, std::uint32_t v) {
  e.writer().u32(v);
}
inline void encode_binary(Encoder& e, std::int64_t v) {
  e.writer().i64(v);
}
inline void encode_binary(Encoder& e, std::uint64_t v) {
  e.writer().u64(v);
}
inline void encode_binary(Encoder& e, float v) {
  e.writer().f32(v);
}
inline void encode_binary(Encoder& e, double v) {
  e.writer().f64(v);
}
inline void encode_binary(Encoder& e, DateTime v) {
  e.writer().i64(v.ticks());
}
inline void encode_binary(Encoder& e, StatusCode v) {
  e.writer().u32(v.value());
}
void encode_binary(Encoder& e, const String& v);
void encode_binary(Encoder& e, const ByteString& v);
void encode_binary(Encoder& e, const XmlElement& v);
void encode_binary(Encoder& e, const Guid& v);
void encode_binary(Encoder& e, const NodeId& v);
void encode_binary(Encoder& e, const ExpandedNodeId& v);
void encode_binary(Encoder& e, const QualifiedName& v);
void encode_binary(Encoder& e, const LocalizedText& v);
void encode_binary(Encoder& e, const ExtensionObject& v);
void encode_binary(Encoder& e, const Variant& v);
void encode_binary(Encoder& e, const DataValue& v);
void encode_binary(Encoder& e, const DiagnosticInfo& v);

// A Boolean is one byte; any non-zero value is true (OPC 10000-6 §5.2.2.1).
inline void decode_binary(Decoder& d, bool& v) {
  v = d.reader().u8() != 0;
}
inline void decode_binary(Decoder& d, std::int8_t& v) {
  v = d.reader().i8();
}
inline void decode_binary(Decoder& d, std::uint8_t& v) {
  v = d.reader().u8();
}
inline void decode_binary(Decoder& d, std::int16_t& v) {
  v = d.reader().i16();
}
inline void decode_binary(Decoder& d, std::uint16_t& v) {
  v = d.reader().u16();
}
inline void decode_binary(Decoder& d, std::int32_t& v) {
  v = d.reader().i32();
}
inline void decode_binary(Decoder& d, std::uint32_t& v) {
  v = d.reader().u32();
}
inline void decode_binary(Decoder& d, std::int64_t& v) {
  v = d.reader().i64();
}
inline void decode_binary(Decoder& d, std::uint64_t& v) {
  v = d.reader().u64();
}
inline void decode_binary(Decoder& d, float& v) {
  v = d.reader().f32();
}
inline void decode_binary(Decoder& d, double& v) {
  v = d.reader().f64();
}
inline void decode_binary(Decoder& d, DateTime& v) {
  v = DateTime{d.reader().i64()};
}
inline void decode_binary(Decoder& d, StatusCode& v) {
  v = StatusCode{d.reader().u32()};
}
void decode_binary(Decoder& d, String& v);
void decode_binary(Decoder& d, ByteString& v);
void decode_binary(Decoder& d, XmlElement& v);
void decode_binary(Decoder& d, Guid& v);
void decode_binary(Decoder& d, NodeId& v);
void decode_binary(Decoder& d, ExpandedNodeId& v);
void decode_binary(Decoder& d, QualifiedName& v);
void decode_binary(Decoder& d, LocalizedText& v);
void decode_binary(Decoder& d, ExtensionObject& v);
void decode_binary(Decoder& d, Variant& v);
void decode_binary(Decoder& d, DataValue& v);
void decode_binary(Decoder& d, DiagnosticInfo& v);

// Enumerations are Int32 on the wire (OPC 10000-6 §5.2.4); unknown values are kept as they are.
template <typename E>
requires std::is_enum_v<E> && std::is_same_v<std::underlying_type_t<E>, std::int32_t>
void encode_binary(Encoder& e, E v) {
  e.writer().i32(static_cast<std::int32_t>(v));
}
template <typename E>
requires std::is_enum_v<E> && std::is_same_v<std::underlying_type_t<E>, std::int32_t>
void decode_binary(Decoder& d, E& v) {
  v = static_cast<E>(d.reader().i32());
}

// The fewest bytes one encoded T can take: bounds array lengths before allocating.
template <typename T>
constexpr std::size_t min_encoded_size() {
  if constexpr (requires { T::kMinEncodedSize; }) {
    return T::kMinEncodedSize;
  } else if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
    return sizeof(T);
  } else if constexpr (std::is_same_v<T, DateTime>) {
    return 8;
  } else if constexpr (std::is_same_v<T, Guid>) {
    return 16;
  } else if constexpr (std::is_same_v<T, String> || std::is_same_v<T, ByteString> ||
                       std::is_same_v<T, XmlElement> || std::is_same_v<T, StatusCode>) {
    return 4;
  } else if constexpr (std::is_same_v<T, NodeId> || std::is_same_v<T, ExpandedNodeId>) {
    return 2;
  } else if constexpr (std::is_same_v<T, QualifiedName>) {
    return 6;
  } else if constexpr (std::is_same_v<T, ExtensionObject>) {
    return 3;
  } else {
    return 1;  // LocalizedText, Variant, DataValue, DiagnosticInfo: one mask byte
  }
}

namespace detail {
// Plain numbers whose in-memory layout equals the wire layout on a little-endian host, so
// arrays of them are copied in one go.
template <typename T>
inline constexpr bool kBulkCopy =
    std::endian::native == std::endian::little&& std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;

std::string index_segment(std::size_t index);
}  // namespace detail

// One-dimensional arrays (OPC 10000-6 §5.2.5): Int32 length (-1 = null), then the elements.
template <typename T>
void encode_binary(Encoder& e, const Array<T>& values) {
  if (values.is_null()) {
    e.writer().i32(-1);
    return;
  }
  e.write_length(values.size(), "array");
  if constexpr (detail::kBulkCopy<T>) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(values.data());
    e.writer().bytes(ByteSpan(p, values.size() * sizeof(T)));
  } else {
    for (const auto& v : values) {
      encode_binary(e, static_cast<const T&>(v));
    }
  }
}

template <typename T>
void decode_binary(Decoder& d, Array<T>& values) {
  const std::int64_t n = d.read_length("array", min_encoded_size<T>(), d.limits().max_array_length);
  if (n < 0) {
    if (n == -1) {
      values.set_null();
    }
    return;
  }
  const auto count = static_cast<std::size_t>(n);
  // Elements already there are decoded over, so a reused array keeps their capacity.
  values.resize(count);
  values.set_present();
  if constexpr (detail::kBulkCopy<T>) {
    const ByteSpan raw = d.reader().bytes(count * sizeof(T));
    if (!raw.empty()) {
      std::memcpy(values.data(), raw.data(), raw.size());
    }
  } else if constexpr (std::is_same_v<T, bool>) {
    for (std::size_t i = 0; i < count; ++i) {
      values[i] = d.reader().u8() != 0;
    }
  } else {
    for (std::size_t i = 0; i < count; ++i) {
      decode_binary(d, values[i]);
      if (!d.ok()) {
        d.add_context(detail::index_segment(i));
        return;
      }
    }
  }
}

// ---- Whole values ----------------------------------------------------------------------------

template <typename T>
concept BinaryEncodable = requires(Encoder& e, Decoder& d, const T& cv, T& v) {
  encode_binary(e, cv);
  decode_binary(d, v);
};

// Appends the binary encoding of value to out.
template <BinaryEncodable T>
Status encode(const T& value, ByteWriter& out) {
  Encoder e(out);
  encode_binary(e, value);
  if (!e.ok()) {
    return e.error();
  }
  return {};
}

template <BinaryEncodable T>
Result<Bytes> encode(const T& value) {
  ByteWriter w;
  if (auto st = encode(value, w); !st) {
    return st.error();
  }
  return w.take();
}

// Decodes one T from the reader's current position.
template <BinaryEncodable T>
Status decode(ByteReader& in, T& out, const DecodeOptions& options = {}) {
  Decoder d(in, options);
  decode_binary(d, out);
  if (!d.ok()) {
    if constexpr (EncodableStructure<T>) {
      d.add_context(T::kTypeName);
    }
    return d.error();
  }
  return {};
}

// Decodes a T that must fill all of bytes; trailing bytes are a BadDecodingError.
Status check_trailing(const ByteReader& in, std::string_view what);

template <BinaryEncodable T>
Result<T> decode(ByteSpan bytes, const DecodeOptions& options = {}) {
  ByteReader r(bytes);
  T value{};
  if (auto st = decode(r, value, options); !st) {
    return st.error();
  }
  std::string_view what = "value";
  if constexpr (EncodableStructure<T>) {
    what = T::kTypeName;
  }
  if (auto st = check_trailing(r, what); !st) {
    return st.error();
  }
  return value;
}

}  // namespace sf::opcua
