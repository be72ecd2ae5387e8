// OPC UA Binary encoding of Variant (OPC 10000-6 §5.2.2.16), DataValue (§5.2.2.17) and
// DiagnosticInfo (§5.2.2.12).
#include <algorithm>
#include <array>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "opcua_internal.hpp"
#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

// ---- Variant ----------------------------------------------------------------------------------

namespace {

constexpr std::uint8_t kTypeMask = 0x3F;
constexpr std::uint8_t kArrayDimensionsFlag = 0x40;
constexpr std::uint8_t kArrayFlag = 0x80;
constexpr std::uint8_t kMaxBuiltinType = 25;
// Ids 26..31 are reserved: decoders read them as ByteString (§5.2.2.16).
constexpr std::uint8_t kMaxReservedType = 31;

// The C++ type of each built-in type id; element i is id i + 1.
using BuiltinTypes =
    std::tuple<bool, std::int8_t, std::uint8_t, std::int16_t, std::uint16_t, std::int32_t, std::uint32_t,
               std::int64_t, std::uint64_t, float, double, String, DateTime, Guid, ByteString, XmlElement,
               NodeId, ExpandedNodeId, StatusCode, QualifiedName, LocalizedText, ExtensionObject, DataValue,
               Variant, DiagnosticInfo>;

template <typename T>
void decode_variant_value(Decoder& d, Variant::Storage& storage, bool array) {
  if (array) {
    decode_binary(d, storage.emplace<Array<T>>());
  } else if constexpr (std::is_same_v<T, Variant>) {
    d.fail(status::BadDecodingError, "a Variant cannot hold a scalar Variant");
  } else if constexpr (detail::VariantBoxed<T>::value) {
    decode_binary(d, *storage.emplace<Box<T>>(T{}));
  } else {
    decode_binary(d, storage.emplace<T>());
  }
}

using DecodeValueFn = void (*)(Decoder&, Variant::Storage&, bool);

template <std::size_t... I>
constexpr std::array<DecodeValueFn, sizeof...(I)> make_decoders(std::index_sequence<I...>) {
  return {&decode_variant_value<std::tuple_element_t<I, BuiltinTypes>>...};
}

constexpr auto kDecoders = make_decoders(std::make_index_sequence<std::tuple_size_v<BuiltinTypes>>{});

void decode_array_dimensions(Decoder& d, Variant& v) {
  Array<std::int32_t> dims;
  decode_binary(d, dims);
  if (!d.ok()) {
    d.add_context("arrayDimensions");
    return;
  }
  if (auto st = v.set_array_dimensions(std::vector<std::int32_t>(dims.begin(), dims.end())); !st) {
    d.fail(status::BadDecodingError, fmt::format("arrayDimensions [{}] do not match the {} element(s)",
                                                 fmt::join(dims, ","), v.array_length()));
  }
}

// Writes mask and value of a scalar of fixed size (numbers, DateTime, StatusCode, Guid) into
// out and returns true; false for every other Variant. Encoding such values through a stack
// buffer saves a buffer resize per field on the hottest path (DataValues of numbers).
bool encode_fixed_scalar(const Variant& v, SpanWriter& out) {
  return std::visit(
      [&out, &v](const auto& value) {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_arithmetic_v<T>) {
          out.u8(static_cast<std::uint8_t>(v.type()));
          if constexpr (std::is_same_v<T, bool>) {
            out.u8(value ? 1 : 0);
          } else {
            out.write(value);
          }
          return true;
        } else if constexpr (std::is_same_v<T, DateTime>) {
          out.u8(static_cast<std::uint8_t>(BuiltinType::DateTime));
          out.write(value.ticks());
          return true;
        } else if constexpr (std::is_same_v<T, StatusCode>) {
          out.u8(static_cast<std::uint8_t>(BuiltinType::StatusCode));
          out.u32(value.value());
          return true;
        } else if constexpr (std::is_same_v<T, Guid>) {
          out.u8(static_cast<std::uint8_t>(BuiltinType::Guid));
          out.u32(value.data1);
          out.u16(value.data2);
          out.u16(value.data3);
          out.bytes(value.data4);
          return true;
        } else {
          return false;
        }
      },
      v.storage());
}

// Room for the largest fixed scalar (a Guid) with its mask.
constexpr std::size_t kFixedScalarRoom = 17;

}  // namespace

void encode_binary(Encoder& e, const Variant& v) {
  if (v.is_empty()) {
    e.writer().u8(0);
    return;
  }
  if (v.is_scalar()) {
    std::array<std::uint8_t, kFixedScalarRoom> buffer{};
    SpanWriter out(buffer);
    if (encode_fixed_scalar(v, out)) {
      e.writer().bytes(ByteSpan(buffer).first(out.position()));
      return;
    }
  }
  DepthGuard guard(e, "Variant");
  if (!guard) {
    return;
  }
  auto mask = static_cast<std::uint8_t>(v.type());
  if (v.is_array()) {
    mask |= kArrayFlag;
  }
  const auto& dims = v.array_dimensions();
  if (!dims.empty()) {
    if (!v.is_array() || !dimensions_match(dims, v.array_length())) {
      e.fail(status::BadEncodingError,
             fmt::format("Variant arrayDimensions [{}] do not match the {} element(s)", fmt::join(dims, ","),
                         v.array_length()));
      return;
    }
    mask |= kArrayDimensionsFlag;
  }
  e.writer().u8(mask);
  std::visit(
      [&e](const auto& value) {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
        } else if constexpr (requires {
                               value.get();
                               value.has_value();
                             }) {
          encode_binary(e, *value);  // a boxed scalar
        } else {
          encode_binary(e, value);
        }
      },
      v.storage());
  if (!dims.empty()) {
    e.write_length(dims.size(), "arrayDimensions");
    for (std::int32_t dim : dims) {
      e.writer().i32(dim);
    }
  }
}

void decode_binary(Decoder& d, Variant& v) {
  DepthGuard guard(d, "Variant");
  if (!guard) {
    return;
  }
  const std::uint8_t mask = d.reader().u8();
  v.clear();
  if (!d.ok()) {
    return;
  }
  std::uint8_t type = mask & kTypeMask;
  const bool array = (mask & kArrayFlag) != 0;
  const bool has_dimensions = (mask & kArrayDimensionsFlag) != 0;
  if (type == 0) {
    if (mask != 0) {
      d.fail(status::BadDecodingError, fmt::format("Variant mask 0x{:02x} has flags but no type", mask));
    }
    return;
  }
  if (has_dimensions && !array) {
    d.fail(status::BadDecodingError, fmt::format("Variant mask 0x{:02x} has dimensions but no array", mask));
    return;
  }
  if (type > kMaxBuiltinType) {
    if (type > kMaxReservedType) {
      d.fail(status::BadDecodingError, fmt::format("Variant has unknown built-in type {}", type));
      return;
    }
    type = static_cast<std::uint8_t>(BuiltinType::ByteString);
  }
  kDecoders[type - 1U](d, v.storage(), array);
  if (!d.ok()) {
    d.add_context(fmt::format("{{{}{}}}", to_string(static_cast<BuiltinType>(type)), array ? "[]" : ""));
    return;
  }
  if (has_dimensions) {
    decode_array_dimensions(d, v);
  }
}

// ---- DataValue --------------------------------------------------------------------------------

namespace {
constexpr std::uint8_t kHasValue = 0x01;
constexpr std::uint8_t kHasStatus = 0x02;
constexpr std::uint8_t kHasSourceTimestamp = 0x04;
constexpr std::uint8_t kHasServerTimestamp = 0x08;
constexpr std::uint8_t kHasSourcePicoseconds = 0x10;
constexpr std::uint8_t kHasServerPicoseconds = 0x20;
constexpr std::uint16_t kMaxPicoseconds = 9999;

std::uint8_t data_value_mask(const DataValue& v) {
  std::uint8_t mask = 0;
  if (!v.value.is_empty()) {
    mask |= kHasValue;
  }
  if (v.status != StatusCode{}) {
    mask |= kHasStatus;
  }
  if (v.source_timestamp.ticks() != 0) {
    mask |= kHasSourceTimestamp;
  }
  if (v.server_timestamp.ticks() != 0) {
    mask |= kHasServerTimestamp;
  }
  if (v.source_picoseconds != 0) {
    mask |= kHasSourcePicoseconds;
  }
  if (v.server_picoseconds != 0) {
    mask |= kHasServerPicoseconds;
  }
  return mask;
}

// §5.2.2.17: values of 10000 or more are read as 9999.
std::uint16_t read_picoseconds(Decoder& d) {
  return std::min(d.reader().u16(), kMaxPicoseconds);
}
}  // namespace

void encode_binary(Encoder& e, const DataValue& v) {
  // A DataValue of a fixed-size scalar leaves in one write from a stack buffer; otherwise the
  // value is encoded in between the mask and the fixed-size fields.
  std::array<std::uint8_t, 1 + kFixedScalarRoom + 24> fixed{};
  SpanWriter w(fixed);
  const std::uint8_t mask = data_value_mask(v);
  w.u8(mask);
  if ((mask & kHasValue) != 0 && !(v.value.is_scalar() && encode_fixed_scalar(v.value, w))) {
    e.writer().bytes(ByteSpan(fixed).first(w.position()));
    encode_binary(e, v.value);
    w = SpanWriter(fixed);
  }
  if ((mask & kHasStatus) != 0) {
    w.u32(v.status.value());
  }
  if ((mask & kHasSourceTimestamp) != 0) {
    w.write(v.source_timestamp.ticks());
  }
  if ((mask & kHasSourcePicoseconds) != 0) {
    w.u16(v.source_picoseconds);
  }
  if ((mask & kHasServerTimestamp) != 0) {
    w.write(v.server_timestamp.ticks());
  }
  if ((mask & kHasServerPicoseconds) != 0) {
    w.u16(v.server_picoseconds);
  }
  e.writer().bytes(ByteSpan(fixed).first(w.position()));
}

void decode_binary(Decoder& d, DataValue& v) {
  ByteReader& r = d.reader();
  const std::uint8_t mask = r.u8();
  if (!d.ok()) {
    return;
  }
  if ((mask & 0xC0U) != 0) {
    d.fail(status::BadDecodingError, fmt::format("DataValue encoding mask 0x{:02x} has unknown bits", mask));
    return;
  }
  if ((mask & kHasValue) != 0) {
    decode_binary(d, v.value);
    if (!d.ok()) {
      d.add_context("value");
      return;
    }
  } else {
    v.value.clear();
  }
  v.status = (mask & kHasStatus) != 0 ? StatusCode{r.u32()} : StatusCode{};
  v.source_timestamp = DateTime{(mask & kHasSourceTimestamp) != 0 ? r.i64() : 0};
  v.source_picoseconds = (mask & kHasSourcePicoseconds) != 0 ? read_picoseconds(d) : 0;
  v.server_timestamp = DateTime{(mask & kHasServerTimestamp) != 0 ? r.i64() : 0};
  v.server_picoseconds = (mask & kHasServerPicoseconds) != 0 ? read_picoseconds(d) : 0;
}

// ---- DiagnosticInfo ---------------------------------------------------------------------------

namespace {
constexpr std::uint8_t kHasSymbolicId = 0x01;
constexpr std::uint8_t kHasNamespaceUri = 0x02;
constexpr std::uint8_t kHasLocalizedText = 0x04;
constexpr std::uint8_t kDiagnosticHasLocale = 0x08;
constexpr std::uint8_t kHasAdditionalInfo = 0x10;
constexpr std::uint8_t kHasInnerStatusCode = 0x20;
constexpr std::uint8_t kHasInnerDiagnosticInfo = 0x40;

std::uint8_t diagnostic_info_mask(const DiagnosticInfo& v) {
  std::uint8_t mask = 0;
  if (v.symbolic_id != -1) {
    mask |= kHasSymbolicId;
  }
  if (v.namespace_uri != -1) {
    mask |= kHasNamespaceUri;
  }
  if (v.localized_text != -1) {
    mask |= kHasLocalizedText;
  }
  if (v.locale != -1) {
    mask |= kDiagnosticHasLocale;
  }
  if (!v.additional_info.is_null()) {
    mask |= kHasAdditionalInfo;
  }
  if (v.inner_status_code != StatusCode{}) {
    mask |= kHasInnerStatusCode;
  }
  if (v.inner_diagnostic_info) {
    mask |= kHasInnerDiagnosticInfo;
  }
  return mask;
}
}  // namespace

void encode_binary(Encoder& e, const DiagnosticInfo& v) {
  DepthGuard guard(e, "DiagnosticInfo");
  if (!guard) {
    return;
  }
  const std::uint8_t mask = diagnostic_info_mask(v);
  ByteWriter& w = e.writer();
  w.u8(mask);
  // Field order of §5.2.2.12: SymbolicId, NamespaceUri, Locale, LocalizedText, ...
  if ((mask & kHasSymbolicId) != 0) {
    w.i32(v.symbolic_id);
  }
  if ((mask & kHasNamespaceUri) != 0) {
    w.i32(v.namespace_uri);
  }
  if ((mask & kDiagnosticHasLocale) != 0) {
    w.i32(v.locale);
  }
  if ((mask & kHasLocalizedText) != 0) {
    w.i32(v.localized_text);
  }
  if ((mask & kHasAdditionalInfo) != 0) {
    encode_binary(e, v.additional_info);
  }
  if ((mask & kHasInnerStatusCode) != 0) {
    w.u32(v.inner_status_code.value());
  }
  if ((mask & kHasInnerDiagnosticInfo) != 0) {
    encode_binary(e, *v.inner_diagnostic_info);
  }
}

void decode_binary(Decoder& d, DiagnosticInfo& v) {
  DepthGuard guard(d, "DiagnosticInfo");
  if (!guard) {
    return;
  }
  ByteReader& r = d.reader();
  const std::uint8_t mask = r.u8();
  if (!d.ok()) {
    return;
  }
  if ((mask & 0x80U) != 0) {
    d.fail(status::BadDecodingError,
           fmt::format("DiagnosticInfo encoding mask 0x{:02x} has unknown bits", mask));
    return;
  }
  v.symbolic_id = (mask & kHasSymbolicId) != 0 ? r.i32() : -1;
  v.namespace_uri = (mask & kHasNamespaceUri) != 0 ? r.i32() : -1;
  v.locale = (mask & kDiagnosticHasLocale) != 0 ? r.i32() : -1;
  v.localized_text = (mask & kHasLocalizedText) != 0 ? r.i32() : -1;
  if ((mask & kHasAdditionalInfo) != 0) {
    decode_binary(d, v.additional_info);
  } else {
    v.additional_info.set_null();
  }
  v.inner_status_code = (mask & kHasInnerStatusCode) != 0 ? StatusCode{r.u32()} : StatusCode{};
  if ((mask & kHasInnerDiagnosticInfo) != 0) {
    decode_binary(d, v.inner_diagnostic_info.emplace());
    if (!d.ok()) {
      d.add_context("innerDiagnosticInfo");
    }
  } else {
    v.inner_diagnostic_info.reset();
  }
}

}  // namespace sf::opcua
