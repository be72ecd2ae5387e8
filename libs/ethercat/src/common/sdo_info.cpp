// SDO Information service messages (ETG.1000.6 §5.6.3): header, service
// data of each opcode, fragmentation and reassembly.
#include "sf/ethercat/sdo_info.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "sf/ethercat/mailbox.hpp"

namespace sf::ethercat {
namespace {

constexpr std::uint8_t kOpCodeMask = 0x7F;
constexpr std::uint8_t kIncomplete = 0x80;
// Bytes of a mailbox taken before SDO Info service data begins.
constexpr std::size_t kSdoInfoOverhead = kMailboxHeaderSize + kCoeHeaderSize + kSdoInfoHeaderSize;
// A reassembled response larger than this is refused (65535 fragments of a
// small mailbox would otherwise grow without bound).
constexpr std::size_t kMaxReassembled = 256 * 1024;

struct Encoder {
  Bytes& out;
  void operator()(const OdListRequest& m) const {
    ByteWriter(out).u16(static_cast<std::uint16_t>(m.list_type));
  }
  void operator()(const OdListResponse& m) const {
    ByteWriter w(out);
    w.u16(static_cast<std::uint16_t>(m.list_type));
    for (const auto index : m.indices) {
      w.u16(index);
    }
  }
  void operator()(const ObjectDescriptionRequest& m) const { ByteWriter(out).u16(m.index); }
  void operator()(const ObjectDescription& m) const {
    ByteWriter w(out);
    w.u16(m.index);
    w.u16(m.data_type);
    w.u8(m.max_subindex);
    w.u8(m.object_code);
    w.bytes(ByteSpan(reinterpret_cast<const std::uint8_t*>(m.name.data()), m.name.size()));  // NOLINT
  }
  void operator()(const EntryDescriptionRequest& m) const {
    ByteWriter w(out);
    w.u16(m.index);
    w.u8(m.subindex);
    w.u8(m.value_info);
  }
  void operator()(const EntryDescription& m) const {
    ByteWriter w(out);
    w.u16(m.index);
    w.u8(m.subindex);
    w.u8(m.value_info);
    w.u16(m.data_type);
    w.u16(m.bit_length);
    w.u16(m.object_access);
    w.bytes(m.values);
    w.bytes(ByteSpan(reinterpret_cast<const std::uint8_t*>(m.name.data()), m.name.size()));  // NOLINT
  }
  void operator()(const SdoInfoError& m) const { ByteWriter(out).u32(m.code); }
};

std::string text_of(ByteSpan bytes) {
  std::string s(bytes.begin(), bytes.end());
  // Some servers pad names with NULs.
  s.erase(std::find(s.begin(), s.end(), '\0'), s.end());
  return s;
}

Result<SdoInfoMessage> checked(ByteReader& r, SdoInfoMessage message, std::string_view what) {
  if (!r.ok()) {
    return r.error(what);
  }
  return message;
}

Result<SdoInfoMessage> decode_od_list(ByteReader& r, bool response) {
  const auto type = r.u16();
  if (!response) {
    return checked(r, OdListRequest{static_cast<OdListType>(type)}, "SDO Info Get OD List request");
  }
  OdListResponse m{static_cast<OdListType>(type), {}};
  if (r.remaining() % 2 != 0) {
    return make_error(Errc::malformed, "SDO Info Get OD List response: odd number of index bytes");
  }
  while (r.ok() && !r.at_end()) {
    m.indices.push_back(r.u16());
  }
  return checked(r, std::move(m), "SDO Info Get OD List response");
}

Result<SdoInfoMessage> decode_object(ByteReader& r) {
  ObjectDescription m;
  m.index = r.u16();
  m.data_type = r.u16();
  m.max_subindex = r.u8();
  m.object_code = r.u8();
  m.name = text_of(r.rest());
  return checked(r, std::move(m), "SDO Info object description");
}

// Bytes of the optional data an entry description announces: unit type
// (UNSIGNED32), then default, minimum and maximum of the entry's size.
std::size_t values_size(std::uint8_t info, std::uint16_t bit_length) {
  const std::size_t value = (bit_length + 7U) / 8U;
  std::size_t n = (info & value_info::kUnitType) != 0 ? 4U : 0U;
  for (const auto bit : {value_info::kDefault, value_info::kMinimum, value_info::kMaximum}) {
    n += (info & bit) != 0 ? value : 0U;
  }
  return n;
}

Result<SdoInfoMessage> decode_entry(ByteReader& r) {
  EntryDescription m;
  m.index = r.u16();
  m.subindex = r.u8();
  m.value_info = r.u8();
  m.data_type = r.u16();
  m.bit_length = r.u16();
  m.object_access = r.u16();
  const ByteSpan values = r.bytes(values_size(m.value_info, m.bit_length));
  m.values.assign(values.begin(), values.end());
  m.name = text_of(r.rest());
  return checked(r, std::move(m), "SDO Info entry description");
}

}  // namespace

std::array<std::uint8_t, kSdoInfoHeaderSize> SdoInfoHeader::encode() const {
  std::array<std::uint8_t, kSdoInfoHeaderSize> out{};
  out[0] = static_cast<std::uint8_t>((opcode & kOpCodeMask) | (incomplete ? kIncomplete : 0U));
  store_le<std::uint16_t>(out.data() + 2, fragments_left);
  return out;
}

Result<SdoInfoHeader> SdoInfoHeader::decode(ByteSpan body) {
  if (body.size() < kSdoInfoHeaderSize) {
    return make_error(Errc::malformed,
                      fmt::format("SDO Info header needs {} bytes, got {}", kSdoInfoHeaderSize, body.size()));
  }
  return SdoInfoHeader{static_cast<std::uint8_t>(body[0] & kOpCodeMask), (body[0] & kIncomplete) != 0,
                       load_le<std::uint16_t>(body.data() + 2)};
}

SdoInfoOpCode opcode_of(const SdoInfoMessage& message) {
  // The variant's alternatives are in opcode order (1..7).
  return static_cast<SdoInfoOpCode>(message.index() + 1);
}

Bytes encode_sdo_info_data(const SdoInfoMessage& message) {
  Bytes out;
  std::visit(Encoder{out}, message);
  return out;
}

Result<SdoInfoMessage> decode_sdo_info_data(std::uint8_t opcode, ByteSpan data) {
  ByteReader r(data);
  switch (static_cast<SdoInfoOpCode>(opcode)) {
    case SdoInfoOpCode::GetOdListRequest:
    case SdoInfoOpCode::GetOdListResponse:
      return decode_od_list(r, opcode == static_cast<std::uint8_t>(SdoInfoOpCode::GetOdListResponse));
    case SdoInfoOpCode::GetObjectDescriptionRequest:
      return checked(r, ObjectDescriptionRequest{r.u16()}, "SDO Info object description request");
    case SdoInfoOpCode::GetObjectDescriptionResponse:
      return decode_object(r);
    case SdoInfoOpCode::GetEntryDescriptionRequest: {
      EntryDescriptionRequest m;
      m.index = r.u16();
      m.subindex = r.u8();
      m.value_info = r.u8();
      return checked(r, m, "SDO Info entry description request");
    }
    case SdoInfoOpCode::GetEntryDescriptionResponse:
      return decode_entry(r);
    case SdoInfoOpCode::ErrorRequest:
      return checked(r, SdoInfoError{r.u32()}, "SDO Info error");
  }
  return make_error(Errc::unsupported, fmt::format("SDO Info opcode {} is not defined", opcode));
}

std::vector<Bytes> sdo_info_fragments(const SdoInfoMessage& message, std::size_t mailbox_size) {
  const Bytes data = encode_sdo_info_data(message);
  const std::size_t piece =
      std::max<std::size_t>(2, mailbox_size > kSdoInfoOverhead ? mailbox_size - kSdoInfoOverhead : 0);
  const std::size_t count = std::max<std::size_t>(1, (data.size() + piece - 1) / piece);
  std::vector<Bytes> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t left = count - 1 - i;
    SdoInfoHeader h{static_cast<std::uint8_t>(opcode_of(message)), left > 0,
                    static_cast<std::uint16_t>(std::min<std::size_t>(left, 0xFFFF))};
    const auto header = h.encode();
    Bytes body(header.begin(), header.end());
    const std::size_t from = i * piece;
    const std::size_t to = std::min(data.size(), from + piece);
    body.insert(body.end(), data.begin() + static_cast<std::ptrdiff_t>(from),
                data.begin() + static_cast<std::ptrdiff_t>(to));
    out.push_back(std::move(body));
  }
  return out;
}

Bytes make_sdo_info(const SdoInfoMessage& message, std::uint8_t counter, std::uint16_t address) {
  const auto header = SdoInfoHeader{static_cast<std::uint8_t>(opcode_of(message)), false, 0}.encode();
  Bytes body(header.begin(), header.end());
  const Bytes data = encode_sdo_info_data(message);
  body.insert(body.end(), data.begin(), data.end());
  MailboxHeader mailbox;
  mailbox.address = address;
  mailbox.counter = counter;
  return encode_coe(mailbox, CoeHeader{0, CoeService::SdoInformation}, body);
}

Result<std::optional<SdoInfoMessage>> SdoInfoReassembly::add(ByteSpan body) {
  auto result = add_fragment(body);
  if (!result || *result) {
    first_.reset();  // done or broken: the next fragment starts a new response
    data_.clear();
  }
  return result;
}

Result<std::optional<SdoInfoMessage>> SdoInfoReassembly::add_fragment(ByteSpan body) {
  auto header = SdoInfoHeader::decode(body);
  if (!header) {
    return header.error();
  }
  if (first_) {
    if (header->opcode != first_->opcode || header->fragments_left + 1U != expected_left_) {
      return make_error(Errc::malformed,
                        fmt::format("SDO Info fragment: opcode {} with {} left does not continue opcode {} "
                                    "with {} left",
                                    header->opcode, header->fragments_left, first_->opcode, expected_left_));
    }
  } else {
    first_ = *header;
  }
  expected_left_ = header->fragments_left;
  const ByteSpan data = body.subspan(kSdoInfoHeaderSize);
  if (data_.size() + data.size() > kMaxReassembled) {
    return make_error(Errc::limit_exceeded,
                      fmt::format("SDO Info response exceeds {} bytes", kMaxReassembled));
  }
  data_.insert(data_.end(), data.begin(), data.end());
  // The last fragment: "incomplete" clear (fragments left 0 as well).
  if (header->incomplete && header->fragments_left > 0) {
    return std::optional<SdoInfoMessage>{};
  }
  auto message = decode_sdo_info_data(first_->opcode, data_);
  if (!message) {
    return message.error();
  }
  return std::optional<SdoInfoMessage>{std::move(*message)};
}

std::string data_type_name(std::uint16_t type) {
  switch (type) {
    case data_type::kBoolean:
      return "BOOLEAN";
    case data_type::kInteger8:
      return "INTEGER8";
    case data_type::kInteger16:
      return "INTEGER16";
    case data_type::kInteger32:
      return "INTEGER32";
    case data_type::kUnsigned8:
      return "UNSIGNED8";
    case data_type::kUnsigned16:
      return "UNSIGNED16";
    case data_type::kUnsigned32:
      return "UNSIGNED32";
    case data_type::kReal32:
      return "REAL32";
    case data_type::kVisibleString:
      return "VISIBLE_STRING";
    case data_type::kOctetString:
      return "OCTET_STRING";
    case data_type::kReal64:
      return "REAL64";
    case data_type::kInteger64:
      return "INTEGER64";
    case data_type::kUnsigned64:
      return "UNSIGNED64";
    default:
      return fmt::format("0x{:04X}", type);
  }
}

std::string object_code_name(std::uint8_t object_code) {
  switch (object_code) {
    case 7:
      return "VAR";
    case 8:
      return "ARRAY";
    case 9:
      return "RECORD";
    default:
      return fmt::format("0x{:02X}", object_code);
  }
}

std::string access_text(std::uint16_t access) {
  // Table 49: bits 0–2 read in PREOP/SAFEOP/OP, bits 3–5 write.
  const unsigned reads = access & 0x07U;
  const unsigned writes = (access >> 3U) & 0x07U;
  std::string out = reads == 0 ? (writes == 0 ? "--" : "wo") : (writes == 0 ? "ro" : "rw");
  if (writes != 0 && writes != 0x07U) {
    std::string states;
    for (const auto& [bit, name] : {std::pair{1U, "PREOP"}, std::pair{2U, "SAFEOP"}, std::pair{4U, "OP"}}) {
      if ((writes & bit) != 0) {
        states += (states.empty() ? "" : "+") + std::string{name};
      }
    }
    out += " (write in " + states + ")";
  }
  if ((access & 0x40U) != 0) {
    out += " RxPDO";
  }
  if ((access & 0x80U) != 0) {
    out += " TxPDO";
  }
  return out;
}

namespace {

template <typename T>
std::string format_number(ByteSpan value) {
  std::uint8_t buf[sizeof(T)] = {};
  std::memcpy(buf, value.data(), std::min(sizeof(T), value.size()));
  const T v = load_le<T>(buf);
  if constexpr (std::is_floating_point_v<T>) {
    return fmt::format("{}", v);
  } else if constexpr (std::is_signed_v<T>) {
    return fmt::format("{}", static_cast<std::int64_t>(v));
  } else {
    return fmt::format("{} (0x{:0{}X})", static_cast<std::uint64_t>(v), static_cast<std::uint64_t>(v),
                       2 * sizeof(T));
  }
}

template <typename T>
Result<Bytes> parse_number(std::string_view text) {
  Bytes out(sizeof(T));
  T v{};
  if constexpr (std::is_floating_point_v<T>) {
    const std::string s(text);
    char* end = nullptr;
    const double d = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size()) {
      return make_error(Errc::invalid_argument, fmt::format("'{}' is not a number", text));
    }
    v = static_cast<T>(d);
  } else {
    int base = 10;
    bool negative = false;
    std::string_view digits = text;
    if (!digits.empty() && digits.front() == '-') {
      negative = true;
      digits.remove_prefix(1);
    }
    if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
      base = 16;
      digits.remove_prefix(2);
    }
    std::uint64_t magnitude = 0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), magnitude, base);
    if (digits.empty() || ec != std::errc{} || ptr != digits.data() + digits.size()) {
      return make_error(Errc::invalid_argument, fmt::format("'{}' is not an integer", text));
    }
    const auto max = static_cast<std::uint64_t>(std::numeric_limits<T>::max());
    const bool fits = negative ? std::is_signed_v<T> && magnitude <= max + 1U : magnitude <= max;
    if (!fits) {
      return make_error(Errc::out_of_range, fmt::format("{} does not fit {} bytes", text, sizeof(T)));
    }
    v = negative ? static_cast<T>(0 - magnitude) : static_cast<T>(magnitude);
  }
  store_le<T>(out.data(), v);
  return out;
}

}  // namespace

std::string format_value(std::uint16_t type, ByteSpan value) {
  switch (type) {
    case data_type::kBoolean:
      return value.empty() ? "?" : (value[0] != 0 ? "TRUE" : "FALSE");
    case data_type::kInteger8:
      return format_number<std::int8_t>(value);
    case data_type::kInteger16:
      return format_number<std::int16_t>(value);
    case data_type::kInteger32:
      return format_number<std::int32_t>(value);
    case data_type::kInteger64:
      return format_number<std::int64_t>(value);
    case data_type::kUnsigned8:
      return format_number<std::uint8_t>(value);
    case data_type::kUnsigned16:
      return format_number<std::uint16_t>(value);
    case data_type::kUnsigned32:
      return format_number<std::uint32_t>(value);
    case data_type::kUnsigned64:
      return format_number<std::uint64_t>(value);
    case data_type::kReal32:
      return format_number<float>(value);
    case data_type::kReal64:
      return format_number<double>(value);
    case data_type::kVisibleString:
      return "\"" + text_of(value) + "\"";
    default:
      return to_hex(value, 4096);
  }
}

Result<Bytes> parse_value(std::uint16_t type, std::string_view text) {
  switch (type) {
    case data_type::kBoolean: {
      if (text == "1" || text == "true" || text == "TRUE") {
        return Bytes{1};
      }
      if (text == "0" || text == "false" || text == "FALSE") {
        return Bytes{0};
      }
      return make_error(Errc::invalid_argument, fmt::format("'{}' is not a boolean (0/1/true/false)", text));
    }
    case data_type::kInteger8:
      return parse_number<std::int8_t>(text);
    case data_type::kInteger16:
      return parse_number<std::int16_t>(text);
    case data_type::kInteger32:
      return parse_number<std::int32_t>(text);
    case data_type::kInteger64:
      return parse_number<std::int64_t>(text);
    case data_type::kUnsigned8:
      return parse_number<std::uint8_t>(text);
    case data_type::kUnsigned16:
      return parse_number<std::uint16_t>(text);
    case data_type::kUnsigned32:
      return parse_number<std::uint32_t>(text);
    case data_type::kUnsigned64:
      return parse_number<std::uint64_t>(text);
    case data_type::kReal32:
      return parse_number<float>(text);
    case data_type::kReal64:
      return parse_number<double>(text);
    case data_type::kVisibleString:
      return Bytes(text.begin(), text.end());
    default:
      return from_hex(text);
  }
}

Result<std::uint16_t> data_type_from_name(std::string_view name) {
  static constexpr std::pair<std::string_view, std::uint16_t> kNames[] = {
      {"u8", data_type::kUnsigned8},   {"u16", data_type::kUnsigned16}, {"u32", data_type::kUnsigned32},
      {"u64", data_type::kUnsigned64}, {"i8", data_type::kInteger8},    {"i16", data_type::kInteger16},
      {"i32", data_type::kInteger32},  {"i64", data_type::kInteger64},  {"bool", data_type::kBoolean},
      {"f32", data_type::kReal32},     {"f64", data_type::kReal64},     {"string", data_type::kVisibleString},
      {"hex", data_type::kOctetString}};
  for (const auto& [n, type] : kNames) {
    if (n == name) {
      return type;
    }
  }
  return make_error(
      Errc::invalid_argument,
      fmt::format("unknown type '{}' (u8 u16 u32 u64 i8 i16 i32 i64 bool f32 f64 string hex)", name));
}

}  // namespace sf::ethercat
