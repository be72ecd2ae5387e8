// OPC UA Binary encoding of the scalar built-in types (OPC 10000-6 §5.2.2.4 - §5.2.2.14).
#include <fmt/format.h>

#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

namespace {

// NodeId DataEncoding values (OPC 10000-6 §5.2.2.9, Table 11 in v1.05).
enum NodeIdEncoding : std::uint8_t {
  kTwoByte = 0x00,
  kFourByte = 0x01,
  kNumeric = 0x02,
  kString = 0x03,
  kGuid = 0x04,
  kByteString = 0x05,
};
constexpr std::uint8_t kNamespaceUriFlag = 0x80;  // ExpandedNodeId only (§5.2.2.10)
constexpr std::uint8_t kServerIndexFlag = 0x40;

void write_bytes(Encoder& e, ByteSpan bytes, std::string_view what) {
  e.write_length(bytes.size(), what);
  if (e.ok()) {
    e.writer().bytes(bytes);
  }
}

// Reads an Int32-prefixed run of bytes (a view into the input) into out. Returns false for a
// null run (length -1, and then `null` is set) and after an error.
bool read_bytes(Decoder& d, std::string_view what, ByteSpan& out, bool& null) {
  const std::int64_t n = d.read_length(what, 1, d.limits().max_string_length);
  null = n == -1;
  if (n < 0) {
    return false;
  }
  out = d.reader().bytes(static_cast<std::size_t>(n));
  return d.ok();
}

// Writes the NodeId in its shortest form; `flags` are the ExpandedNodeId bits.
void encode_node_id(Encoder& e, const NodeId& v, std::uint8_t flags) {
  ByteWriter& w = e.writer();
  const std::uint16_t ns = v.namespace_index;
  switch (v.type()) {
    case NodeIdType::Numeric: {
      const std::uint32_t id = v.numeric();
      if (ns == 0 && id <= 0xFFU) {
        w.u8(kTwoByte | flags);
        w.u8(static_cast<std::uint8_t>(id));
      } else if (ns <= 0xFFU && id <= 0xFFFFU) {
        w.u8(kFourByte | flags);
        w.u8(static_cast<std::uint8_t>(ns));
        w.u16(static_cast<std::uint16_t>(id));
      } else {
        w.u8(kNumeric | flags);
        w.u16(ns);
        w.u32(id);
      }
      return;
    }
    case NodeIdType::String:
      w.u8(kString | flags);
      w.u16(ns);
      encode_binary(e, std::get<String>(v.identifier));
      return;
    case NodeIdType::Guid:
      w.u8(kGuid | flags);
      w.u16(ns);
      encode_binary(e, std::get<Guid>(v.identifier));
      return;
    case NodeIdType::Opaque:
      w.u8(kByteString | flags);
      w.u16(ns);
      encode_binary(e, std::get<ByteString>(v.identifier));
      return;
  }
}

// Reads the NodeId that follows an encoding byte whose flag bits are already masked off.
void decode_node_id_body(Decoder& d, std::uint8_t format, NodeId& v) {
  ByteReader& r = d.reader();
  switch (format) {
    case kTwoByte:
      v = NodeId(0, std::uint32_t{r.u8()});
      return;
    case kFourByte: {
      const std::uint8_t ns = r.u8();
      v = NodeId(ns, std::uint32_t{r.u16()});
      return;
    }
    case kNumeric: {
      const std::uint16_t ns = r.u16();
      v = NodeId(ns, r.u32());
      return;
    }
    case kString: {
      v.namespace_index = r.u16();
      decode_binary(d, v.identifier.emplace<String>());
      return;
    }
    case kGuid: {
      v.namespace_index = r.u16();
      decode_binary(d, v.identifier.emplace<Guid>());
      return;
    }
    case kByteString: {
      v.namespace_index = r.u16();
      decode_binary(d, v.identifier.emplace<ByteString>());
      return;
    }
    default:
      d.fail(status::BadDecodingError,
             fmt::format("NodeId encoding byte has unknown format 0x{:02x}", format));
  }
}

}  // namespace

// ---- String, ByteString, XmlElement (§5.2.2.4, §5.2.2.7, §5.2.2.8) ----------------------------

void encode_binary(Encoder& e, const String& v) {
  if (v.is_null()) {
    e.writer().i32(-1);
    return;
  }
  const std::string& s = v.str();
  write_bytes(e, ByteSpan(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), "String");
}

void decode_binary(Decoder& d, String& v) {
  ByteSpan bytes;
  bool null = false;
  if (!read_bytes(d, "String", bytes, null)) {
    if (null) {
      v.set_null();
    }
    return;
  }
  v.assign(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void encode_binary(Encoder& e, const ByteString& v) {
  if (v.is_null()) {
    e.writer().i32(-1);
    return;
  }
  write_bytes(e, v.span(), "ByteString");
}

void decode_binary(Decoder& d, ByteString& v) {
  ByteSpan bytes;
  bool null = false;
  if (!read_bytes(d, "ByteString", bytes, null)) {
    if (null) {
      v.set_null();
    }
    return;
  }
  v.assign(bytes);
}

void encode_binary(Encoder& e, const XmlElement& v) {
  encode_binary(e, v.xml);
}
void decode_binary(Decoder& d, XmlElement& v) {
  decode_binary(d, v.xml);
}

// ---- Guid (§5.2.2.6) --------------------------------------------------------------------------

void encode_binary(Encoder& e, const Guid& v) {
  ByteWriter& w = e.writer();
  w.u32(v.data1);
  w.u16(v.data2);
  w.u16(v.data3);
  w.bytes(v.data4);
}

void decode_binary(Decoder& d, Guid& v) {
  ByteReader& r = d.reader();
  v.data1 = r.u32();
  v.data2 = r.u16();
  v.data3 = r.u16();
  r.copy_to(v.data4);
}

// ---- NodeId, ExpandedNodeId (§5.2.2.9, §5.2.2.10) ---------------------------------------------

void encode_binary(Encoder& e, const NodeId& v) {
  encode_node_id(e, v, 0);
}

void decode_binary(Decoder& d, NodeId& v) {
  const std::uint8_t encoding = d.reader().u8();
  if (!d.ok()) {
    return;
  }
  if ((encoding & (kNamespaceUriFlag | kServerIndexFlag)) != 0) {
    d.fail(status::BadDecodingError,
           fmt::format("NodeId encoding byte 0x{:02x} carries ExpandedNodeId flags", encoding));
    return;
  }
  decode_node_id_body(d, encoding, v);
}

void encode_binary(Encoder& e, const ExpandedNodeId& v) {
  std::uint8_t flags = 0;
  if (!v.namespace_uri.is_null()) {
    flags |= kNamespaceUriFlag;
  }
  if (v.server_index != 0) {
    flags |= kServerIndexFlag;
  }
  encode_node_id(e, v.node_id, flags);
  if (!v.namespace_uri.is_null()) {
    encode_binary(e, v.namespace_uri);
  }
  if (v.server_index != 0) {
    e.writer().u32(v.server_index);
  }
}

void decode_binary(Decoder& d, ExpandedNodeId& v) {
  const std::uint8_t encoding = d.reader().u8();
  if (!d.ok()) {
    return;
  }
  decode_node_id_body(d, encoding & 0x3FU, v.node_id);
  if ((encoding & kNamespaceUriFlag) != 0) {
    decode_binary(d, v.namespace_uri);
  } else {
    v.namespace_uri.set_null();
  }
  v.server_index = (encoding & kServerIndexFlag) != 0 ? d.reader().u32() : 0;
}

// ---- QualifiedName, LocalizedText (§5.2.2.13, §5.2.2.14) -------------------------------------

void encode_binary(Encoder& e, const QualifiedName& v) {
  e.writer().u16(v.namespace_index);
  encode_binary(e, v.name);
}

void decode_binary(Decoder& d, QualifiedName& v) {
  v.namespace_index = d.reader().u16();
  decode_binary(d, v.name);
}

namespace {
constexpr std::uint8_t kTextHasLocale = 0x01;
constexpr std::uint8_t kHasText = 0x02;
}  // namespace

void encode_binary(Encoder& e, const LocalizedText& v) {
  std::uint8_t mask = 0;
  if (!v.locale.is_null()) {
    mask |= kTextHasLocale;
  }
  if (!v.text.is_null()) {
    mask |= kHasText;
  }
  e.writer().u8(mask);
  if ((mask & kTextHasLocale) != 0) {
    encode_binary(e, v.locale);
  }
  if ((mask & kHasText) != 0) {
    encode_binary(e, v.text);
  }
}

void decode_binary(Decoder& d, LocalizedText& v) {
  const std::uint8_t mask = d.reader().u8();
  if (!d.ok()) {
    return;
  }
  if ((mask & ~(kTextHasLocale | kHasText)) != 0) {
    d.fail(status::BadDecodingError,
           fmt::format("LocalizedText encoding mask 0x{:02x} has unknown bits", mask));
    return;
  }
  if ((mask & kTextHasLocale) != 0) {
    decode_binary(d, v.locale);
  } else {
    v.locale.set_null();
  }
  if ((mask & kHasText) != 0) {
    decode_binary(d, v.text);
  } else {
    v.text.set_null();
  }
}

}  // namespace sf::opcua
