// Mailbox header and error reply (ETG.1000.4 §5.6), CoE header and emergency
// (ETG.1000.6 §5.6.1, §5.6.4).
#include "sf/ethercat/mailbox.hpp"

#include <fmt/format.h>

namespace sf::ethercat {

std::string_view to_string(MailboxType t) {
  switch (t) {
    case MailboxType::Err:
      return "ERR";
    case MailboxType::AoE:
      return "AoE";
    case MailboxType::EoE:
      return "EoE";
    case MailboxType::CoE:
      return "CoE";
    case MailboxType::FoE:
      return "FoE";
    case MailboxType::SoE:
      return "SoE";
    case MailboxType::VoE:
      return "VoE";
  }
  return "unknown";
}

// Byte 4: channel bits 5:0, priority bits 7:6. Byte 5: type bits 3:0,
// counter bits 6:4, bit 7 reserved (ETG.1000.4 Table 29).
std::array<std::uint8_t, kMailboxHeaderSize> MailboxHeader::encode() const {
  std::array<std::uint8_t, kMailboxHeaderSize> out{};
  SpanWriter w(out);
  w.u16(length);
  w.u16(address);
  w.u8(static_cast<std::uint8_t>((channel & 0x3FU) | ((priority & 0x03U) << 6U)));
  w.u8(static_cast<std::uint8_t>((static_cast<unsigned>(type) & 0x0FU) | ((counter & 0x07U) << 4U)));
  return out;
}

Result<MailboxHeader> MailboxHeader::decode(ByteSpan bytes) {
  if (bytes.size() < kMailboxHeaderSize) {
    return make_error(Errc::malformed,
                      fmt::format("mailbox header needs {} bytes, got {}", kMailboxHeaderSize, bytes.size()));
  }
  ByteReader r(bytes);
  MailboxHeader h;
  h.length = r.u16();
  h.address = r.u16();
  const std::uint8_t b4 = r.u8();
  const std::uint8_t b5 = r.u8();
  h.channel = static_cast<std::uint8_t>(b4 & 0x3FU);
  h.priority = static_cast<std::uint8_t>(b4 >> 6U);
  h.type = static_cast<MailboxType>(b5 & 0x0FU);
  h.counter = static_cast<std::uint8_t>((b5 >> 4U) & 0x07U);
  return h;
}

Bytes encode_mailbox(MailboxHeader header, ByteSpan data) {
  header.length = static_cast<std::uint16_t>(data.size());
  Bytes out;
  out.reserve(kMailboxHeaderSize + data.size());
  const auto h = header.encode();
  out.insert(out.end(), h.begin(), h.end());
  out.insert(out.end(), data.begin(), data.end());
  return out;
}

Result<MailboxMessage> decode_mailbox(ByteSpan buffer) {
  auto header = MailboxHeader::decode(buffer);
  if (!header) {
    return header.error();
  }
  const std::size_t available = buffer.size() - kMailboxHeaderSize;
  if (header->length > available) {
    return make_error(Errc::malformed, fmt::format("mailbox length {} exceeds the {} bytes after the header",
                                                   header->length, available));
  }
  return MailboxMessage{*header, buffer.subspan(kMailboxHeaderSize, header->length)};
}

std::string_view describe(MailboxError e) {
  switch (e) {
    case MailboxError::Syntax:
      return "syntax of the 6-octet mailbox header is wrong";
    case MailboxError::UnsupportedProtocol:
      return "the mailbox protocol is not supported";
    case MailboxError::InvalidChannel:
      return "channel field contains a wrong value";
    case MailboxError::ServiceNotSupported:
      return "the service in the mailbox protocol is not supported";
    case MailboxError::InvalidHeader:
      return "the mailbox protocol header is wrong";
    case MailboxError::SizeTooShort:
      return "length of received mailbox data is too short";
    case MailboxError::NoMoreMemory:
      return "mailbox protocol cannot be processed: not enough memory";
    case MailboxError::InvalidSize:
      return "the length of the data is inconsistent";
    case MailboxError::ServiceInWork:
      return "mailbox service already in use";
  }
  return "unknown mailbox error";
}

Bytes encode_mailbox_error(MailboxError error, std::uint8_t counter, std::uint16_t address) {
  std::array<std::uint8_t, 4> data{};
  store_le<std::uint16_t>(data.data(), kMailboxErrorServiceType);
  store_le<std::uint16_t>(data.data() + 2, static_cast<std::uint16_t>(error));
  MailboxHeader h;
  h.address = address;
  h.type = MailboxType::Err;
  h.counter = counter;
  return encode_mailbox(h, data);
}

Result<MailboxError> decode_mailbox_error(ByteSpan data) {
  if (data.size() < 4) {
    return make_error(Errc::malformed, fmt::format("mailbox error reply needs 4 bytes, got {}", data.size()));
  }
  const auto type = load_le<std::uint16_t>(data.data());
  if (type != kMailboxErrorServiceType) {
    return make_error(Errc::malformed,
                      fmt::format("mailbox error reply has type 0x{:04X}, expected 0x0001", type));
  }
  return static_cast<MailboxError>(load_le<std::uint16_t>(data.data() + 2));
}

std::string_view to_string(CoeService s) {
  switch (s) {
    case CoeService::Emergency:
      return "Emergency";
    case CoeService::SdoRequest:
      return "SDO request";
    case CoeService::SdoResponse:
      return "SDO response";
    case CoeService::TxPdo:
      return "TxPDO";
    case CoeService::RxPdo:
      return "RxPDO";
    case CoeService::TxPdoRemoteRequest:
      return "TxPDO remote request";
    case CoeService::RxPdoRemoteRequest:
      return "RxPDO remote request";
    case CoeService::SdoInformation:
      return "SDO information";
  }
  return "unknown";
}

std::uint16_t CoeHeader::encode() const {
  return static_cast<std::uint16_t>((number & 0x01FFU) | (static_cast<unsigned>(service) << 12U));
}

Result<CoeHeader> CoeHeader::decode(std::uint16_t value) {
  const unsigned service = value >> 12U;
  if (service < 1 || service > 8) {
    return make_error(Errc::malformed, fmt::format("CoE header: service {} is not defined", service));
  }
  return CoeHeader{static_cast<std::uint16_t>(value & 0x01FFU), static_cast<CoeService>(service)};
}

Bytes encode_coe(MailboxHeader mailbox, CoeHeader coe, ByteSpan body) {
  Bytes data(kCoeHeaderSize + body.size());
  store_le<std::uint16_t>(data.data(), coe.encode());
  std::copy(body.begin(), body.end(), data.begin() + kCoeHeaderSize);
  mailbox.type = MailboxType::CoE;
  return encode_mailbox(mailbox, data);
}

Result<CoeMessage> decode_coe(ByteSpan buffer) {
  auto msg = decode_mailbox(buffer);
  if (!msg) {
    return msg.error();
  }
  if (msg->header.type != MailboxType::CoE) {
    return make_error(Errc::malformed,
                      fmt::format("mailbox type {} ({}) is not CoE", static_cast<unsigned>(msg->header.type),
                                  to_string(msg->header.type)));
  }
  if (msg->data.size() < kCoeHeaderSize) {
    return make_error(Errc::malformed, fmt::format("CoE message of {} bytes has no room for the CoE header",
                                                   msg->data.size()));
  }
  auto coe = CoeHeader::decode(load_le<std::uint16_t>(msg->data.data()));
  if (!coe) {
    return coe.error();
  }
  return CoeMessage{msg->header, *coe, msg->data.subspan(kCoeHeaderSize)};
}

Bytes CoeEmergency::encode() const {
  Bytes out;
  ByteWriter w(out);
  w.u16(error_code);
  w.u8(error_register);
  w.bytes(data);
  return out;
}

Result<CoeEmergency> CoeEmergency::decode(ByteSpan body) {
  ByteReader r(body);
  CoeEmergency e;
  e.error_code = r.u16();
  e.error_register = r.u8();
  r.copy_to(e.data);
  if (!r.ok()) {
    return r.error("CoE emergency");
  }
  return e;
}

}  // namespace sf::ethercat
