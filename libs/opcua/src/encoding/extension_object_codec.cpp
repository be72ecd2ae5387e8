// OPC UA Binary encoding of ExtensionObject (OPC 10000-6 §5.2.2.15) and the registry that turns
// known bodies into typed structures.
#include <limits>

#include <fmt/format.h>

#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

namespace {

enum BodyEncoding : std::uint8_t { kNoBody = 0x00, kBinaryBody = 0x01, kXmlBody = 0x02 };

// Encodes a typed body behind a length that is patched in once the body is written
// (§5.2.2.15 allows the encoder to "seek backwards in the stream").
void encode_typed_body(Encoder& e, const ExtensionBody& body) {
  DepthGuard guard(e, "ExtensionObject");
  if (!guard) {
    return;
  }
  ByteWriter& w = e.writer();
  w.u8(kBinaryBody);
  const std::size_t length_at = w.size();
  w.i32(0);
  body.encode(e);
  if (!e.ok()) {
    e.add_context(fmt::format("{{{}}}", body.type_name()));
    return;
  }
  const std::size_t length = w.size() - length_at - sizeof(std::int32_t);
  if (length > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    e.fail(status::BadEncodingLimitsExceeded, fmt::format("{} body of {} bytes", body.type_name(), length));
    return;
  }
  w.patch<std::int32_t>(length_at, static_cast<std::int32_t>(length));
}

// Decodes a body the registry knows with a decoder confined to the body's bytes.
void decode_typed_body(Decoder& d, const NodeId& type_id, ByteSpan body, std::size_t body_offset,
                       const ExtensionRegistry::Entry& entry, ExtensionObject& out) {
  DepthGuard guard(d, "ExtensionObject");
  if (!guard) {
    return;
  }
  ByteReader reader(body);
  DecodeOptions options = d.options();
  options.registry = &d.registry();
  Decoder inner(reader, options);
  inner.set_depth(d.depth());
  auto typed = entry.decode(inner);
  if (!inner.ok()) {
    d.adopt(inner, body_offset);
    d.add_context(fmt::format("{{{}}}", entry.type_name));
    return;
  }
  if (reader.remaining() != 0) {
    d.fail(status::BadDecodingError,
           fmt::format("{} trailing byte(s) after the {} body", reader.remaining(), entry.type_name));
    return;
  }
  out = ExtensionObject(type_id, std::move(typed));
}

}  // namespace

void encode_binary(Encoder& e, const ExtensionObject& v) {
  encode_binary(e, v.type_id());
  if (const auto* typed = v.body()) {
    encode_typed_body(e, *typed);
  } else if (const auto* bytes = v.opaque_body()) {
    e.writer().u8(kBinaryBody);
    e.write_length(bytes->size(), "ExtensionObject body");  // a null body is written as empty
    e.writer().bytes(bytes->span());
  } else if (const auto* xml = v.xml_body()) {
    e.writer().u8(kXmlBody);
    encode_binary(e, xml->xml);
  } else {
    e.writer().u8(kNoBody);
  }
}

void decode_binary(Decoder& d, ExtensionObject& v) {
  NodeId type_id;
  decode_binary(d, type_id);
  if (!d.ok()) {
    d.add_context("typeId");
    return;
  }
  const std::uint8_t encoding = d.reader().u8();
  if (!d.ok()) {
    return;
  }
  switch (encoding) {
    case kNoBody:
      v = ExtensionObject(std::move(type_id), nullptr);
      return;
    case kXmlBody: {
      XmlElement xml;
      decode_binary(d, xml);
      v = ExtensionObject::xml(std::move(type_id), std::move(xml));
      return;
    }
    case kBinaryBody:
      break;
    default:
      d.fail(status::BadDecodingError, fmt::format("ExtensionObject encoding 0x{:02x} is unknown", encoding));
      return;
  }
  const std::int64_t n = d.read_length("ExtensionObject body", 1, d.limits().max_string_length);
  if (n == -1) {
    d.fail(status::BadDecodingError, "ExtensionObject binary body without a length");
  }
  if (n < 0) {
    return;
  }
  const std::size_t body_offset = d.reader().position();
  const ByteSpan body = d.reader().bytes(static_cast<std::size_t>(n));
  if (const auto* entry = d.registry().find(type_id)) {
    decode_typed_body(d, type_id, body, body_offset, *entry, v);
  } else {
    // Unknown types stay opaque (§5.2.2.15): the application may know them.
    v = ExtensionObject::opaque(std::move(type_id), ByteString(body));
  }
}

// ---- ExtensionRegistry ------------------------------------------------------------------------

void ExtensionRegistry::add(const NodeId& encoding_id, DecodeFn decode, std::string_view type_name) {
  entries_[encoding_id] = Entry{decode, type_name};
}

const ExtensionRegistry::Entry* ExtensionRegistry::find(const NodeId& encoding_id) const {
  const auto it = entries_.find(encoding_id);
  return it != entries_.end() ? &it->second : nullptr;
}

}  // namespace sf::opcua
