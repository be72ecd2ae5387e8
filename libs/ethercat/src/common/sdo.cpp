// CoE SDO services, ETG.1000.6 §5.6.2 (the CiA 301 SDO protocol in mailbox
// form). Every body starts with a command byte: bits 7:5 command specifier;
// for initiate services bit 4 complete access, bits 3:2 unused bytes of an
// expedited transfer, bit 1 expedited, bit 0 size indicated; for segments
// bit 4 toggle, bits 3:1 unused bytes of a short segment, bit 0 last segment.
#include <algorithm>

#include <fmt/format.h>

#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat {
namespace {

// Client command specifiers (requests) and server command specifiers (responses).
constexpr unsigned kCcsDownloadSegment = 0;
constexpr unsigned kCcsInitiateDownload = 1;
constexpr unsigned kCcsInitiateUpload = 2;
constexpr unsigned kCcsUploadSegment = 3;
constexpr unsigned kScsUploadSegment = 0;
constexpr unsigned kScsDownloadSegment = 1;
constexpr unsigned kScsInitiateUpload = 2;
constexpr unsigned kScsInitiateDownload = 3;
constexpr unsigned kCsAbort = 4;

constexpr std::uint8_t kSizeIndicated = 0x01;
constexpr std::uint8_t kExpedited = 0x02;
constexpr std::uint8_t kCompleteAccess = 0x10;
constexpr std::uint8_t kToggle = 0x10;
constexpr std::uint8_t kLastSegment = 0x01;
constexpr std::size_t kExpeditedMax = 4;

std::uint8_t command_byte(unsigned specifier, unsigned flags) {
  return static_cast<std::uint8_t>((specifier << 5U) | flags);
}

// --- shared layouts -------------------------------------------------------

// Initiate download request and initiate upload response share one layout.
struct InitiateData {
  std::uint16_t index;
  std::uint8_t subindex;
  bool complete_access;
  bool expedited;
  bool size_indicated;
  std::uint32_t complete_size;
  const Bytes& data;
};

Result<Bytes> encode_initiate_data(unsigned specifier, const InitiateData& m, std::string_view what) {
  Bytes out;
  ByteWriter w(out);
  unsigned flags = m.complete_access ? kCompleteAccess : 0U;
  if (m.expedited) {
    if (m.data.empty() || m.data.size() > kExpeditedMax) {
      return make_error(
          Errc::invalid_argument,
          fmt::format("{}: expedited transfer needs 1-4 data bytes, got {}", what, m.data.size()));
    }
    flags |= kExpedited;
    if (m.size_indicated) {
      flags |= kSizeIndicated | static_cast<unsigned>((kExpeditedMax - m.data.size()) << 2U);
    }
  } else {
    if (m.data.size() > m.complete_size) {
      return make_error(Errc::invalid_argument, fmt::format("{}: {} data bytes exceed the complete size {}",
                                                            what, m.data.size(), m.complete_size));
    }
    flags |= kSizeIndicated;
  }
  w.u8(command_byte(specifier, flags));
  w.u16(m.index);
  w.u8(m.subindex);
  if (m.expedited) {
    w.bytes(m.data);
    w.zeros(kExpeditedMax - m.data.size());
  } else {
    w.u32(m.complete_size);
    w.bytes(m.data);
  }
  return out;
}

template <typename T>
Result<T> decode_initiate_data(ByteSpan body, std::string_view what) {
  ByteReader r(body);
  const std::uint8_t cmd = r.u8();
  T m;
  m.index = r.u16();
  m.subindex = r.u8();
  m.complete_access = (cmd & kCompleteAccess) != 0;
  m.expedited = (cmd & kExpedited) != 0;
  m.size_indicated = (cmd & kSizeIndicated) != 0;
  if (m.expedited) {
    const std::size_t unused = m.size_indicated ? (cmd >> 2U) & 0x03U : 0U;
    const ByteSpan data = r.bytes(kExpeditedMax);
    m.data.assign(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(kExpeditedMax - unused));
    m.complete_size = static_cast<std::uint32_t>(m.data.size());
    return m;
  }
  if (!m.size_indicated) {
    return make_error(
        Errc::malformed,
        fmt::format("{} 0x{:04X}:{:02X}: normal transfer without size indicator", what, m.index, m.subindex));
  }
  m.complete_size = r.u32();
  const ByteSpan data = r.rest();
  if (data.size() > m.complete_size) {
    return make_error(Errc::malformed,
                      fmt::format("{} 0x{:04X}:{:02X}: {} data bytes exceed the complete size {}", what,
                                  m.index, m.subindex, data.size(), m.complete_size));
  }
  m.data.assign(data.begin(), data.end());
  return m;
}

// Download segment request and upload segment response share one layout.
Bytes encode_segment_data(unsigned specifier, bool toggle, bool last, const Bytes& data) {
  Bytes out;
  ByteWriter w(out);
  const std::size_t unused = data.size() < kSdoMinSegmentData ? kSdoMinSegmentData - data.size() : 0;
  w.u8(command_byte(
      specifier, (toggle ? kToggle : 0U) | static_cast<unsigned>(unused << 1U) | (last ? kLastSegment : 0U)));
  w.bytes(data);
  w.zeros(unused);
  return out;
}

template <typename T>
Result<T> decode_segment_data(ByteSpan body) {
  const std::uint8_t cmd = body[0];
  const std::size_t unused = (cmd >> 1U) & 0x07U;
  const std::size_t carried = body.size() - 1;
  if (unused > carried) {
    return make_error(Errc::malformed, fmt::format("SDO segment: {} unused bytes of {}", unused, carried));
  }
  T m;
  m.toggle = (cmd & kToggle) != 0;
  m.last = (cmd & kLastSegment) != 0;
  const ByteSpan data = body.subspan(1, carried - unused);
  m.data.assign(data.begin(), data.end());
  return m;
}

// Initiate upload request, initiate download response and abort: command
// byte, index, subindex and 4 bytes.
Bytes encode_addressed(std::uint8_t cmd, std::uint16_t index, std::uint8_t subindex, std::uint32_t value) {
  Bytes out;
  ByteWriter w(out);
  w.u8(cmd);
  w.u16(index);
  w.u8(subindex);
  w.u32(value);
  return out;
}

// Segment acknowledgements: command byte with toggle and 7 reserved bytes.
Bytes encode_toggle_only(unsigned specifier, bool toggle) {
  Bytes out(kSdoBodyMinSize, 0);
  out[0] = command_byte(specifier, toggle ? kToggle : 0U);
  return out;
}

SdoAbort decode_abort(ByteSpan body) {
  SdoAbort a;
  a.index = load_le<std::uint16_t>(body.data() + 1);
  a.subindex = body[3];
  a.code = load_le<std::uint32_t>(body.data() + 4);
  return a;
}

Status check_body(ByteSpan body, std::string_view what) {
  if (body.size() < kSdoBodyMinSize) {
    return make_error(Errc::malformed, fmt::format("{}: SDO body of {} bytes is shorter than the minimum {}",
                                                   what, body.size(), kSdoBodyMinSize));
  }
  return {};
}

template <typename V>
Result<V> lift(auto result) {
  if (!result) {
    return result.error();
  }
  return V{std::move(*result)};
}

// --- visitors -------------------------------------------------------------

struct RequestEncoder {
  Result<Bytes> operator()(const SdoInitiateDownloadRequest& m) const {
    return encode_initiate_data(
        kCcsInitiateDownload,
        {m.index, m.subindex, m.complete_access, m.expedited, m.size_indicated, m.complete_size, m.data},
        "SDO initiate download request");
  }
  Result<Bytes> operator()(const SdoDownloadSegmentRequest& m) const {
    return encode_segment_data(kCcsDownloadSegment, m.toggle, m.last, m.data);
  }
  Result<Bytes> operator()(const SdoInitiateUploadRequest& m) const {
    return encode_addressed(command_byte(kCcsInitiateUpload, m.complete_access ? kCompleteAccess : 0U),
                            m.index, m.subindex, 0);
  }
  Result<Bytes> operator()(const SdoUploadSegmentRequest& m) const {
    return encode_toggle_only(kCcsUploadSegment, m.toggle);
  }
  Result<Bytes> operator()(const SdoAbort& m) const {
    return encode_addressed(command_byte(kCsAbort, 0), m.index, m.subindex, m.code);
  }
};

struct ResponseEncoder {
  Result<Bytes> operator()(const SdoInitiateDownloadResponse& m) const {
    return encode_addressed(command_byte(kScsInitiateDownload, 0), m.index, m.subindex, 0);
  }
  Result<Bytes> operator()(const SdoDownloadSegmentResponse& m) const {
    return encode_toggle_only(kScsDownloadSegment, m.toggle);
  }
  Result<Bytes> operator()(const SdoInitiateUploadResponse& m) const {
    return encode_initiate_data(
        kScsInitiateUpload,
        {m.index, m.subindex, m.complete_access, m.expedited, m.size_indicated, m.complete_size, m.data},
        "SDO initiate upload response");
  }
  Result<Bytes> operator()(const SdoUploadSegmentResponse& m) const {
    return encode_segment_data(kScsUploadSegment, m.toggle, m.last, m.data);
  }
  Result<Bytes> operator()(const SdoAbort& m) const { return RequestEncoder{}(m); }
};

template <typename T>
T make_initiate(std::uint16_t index, std::uint8_t subindex, ByteSpan object, std::size_t capacity,
                bool complete_access) {
  T m;
  m.index = index;
  m.subindex = subindex;
  m.complete_access = complete_access;
  m.expedited = !object.empty() && object.size() <= kExpeditedMax;
  m.size_indicated = true;
  m.complete_size = static_cast<std::uint32_t>(object.size());
  const std::size_t n = m.expedited ? object.size() : std::min(capacity, object.size());
  m.data.assign(object.begin(), object.begin() + static_cast<std::ptrdiff_t>(n));
  return m;
}

}  // namespace

SdoInitiateDownloadRequest SdoInitiateDownloadRequest::make(std::uint16_t index, std::uint8_t subindex,
                                                            ByteSpan object, std::size_t capacity,
                                                            bool complete_access) {
  return make_initiate<SdoInitiateDownloadRequest>(index, subindex, object, capacity, complete_access);
}

SdoInitiateUploadResponse SdoInitiateUploadResponse::make(std::uint16_t index, std::uint8_t subindex,
                                                          ByteSpan object, std::size_t capacity,
                                                          bool complete_access) {
  return make_initiate<SdoInitiateUploadResponse>(index, subindex, object, capacity, complete_access);
}

Result<Bytes> encode_sdo_request(const SdoRequest& request) {
  return std::visit(RequestEncoder{}, request);
}

Result<Bytes> encode_sdo_response(const SdoResponse& response) {
  return std::visit(ResponseEncoder{}, response);
}

Result<SdoRequest> decode_sdo_request(ByteSpan body) {
  SF_TRY(check_body(body, "SDO request"));
  const unsigned ccs = body[0] >> 5U;
  switch (ccs) {
    case kCcsDownloadSegment:
      return lift<SdoRequest>(decode_segment_data<SdoDownloadSegmentRequest>(body));
    case kCcsInitiateDownload:
      return lift<SdoRequest>(
          decode_initiate_data<SdoInitiateDownloadRequest>(body, "SDO initiate download request"));
    case kCcsInitiateUpload:
      return SdoRequest{SdoInitiateUploadRequest{load_le<std::uint16_t>(body.data() + 1), body[3],
                                                 (body[0] & kCompleteAccess) != 0}};
    case kCcsUploadSegment:
      return SdoRequest{SdoUploadSegmentRequest{(body[0] & kToggle) != 0}};
    case kCsAbort:
      return SdoRequest{decode_abort(body)};
    default:
      break;
  }
  return make_error(
      Errc::unsupported,
      fmt::format("SDO request: client command specifier {} (block transfer) is not supported", ccs));
}

Result<SdoResponse> decode_sdo_response(ByteSpan body) {
  SF_TRY(check_body(body, "SDO response"));
  const unsigned scs = body[0] >> 5U;
  switch (scs) {
    case kScsUploadSegment:
      return lift<SdoResponse>(decode_segment_data<SdoUploadSegmentResponse>(body));
    case kScsDownloadSegment:
      return SdoResponse{SdoDownloadSegmentResponse{(body[0] & kToggle) != 0}};
    case kScsInitiateUpload:
      return lift<SdoResponse>(
          decode_initiate_data<SdoInitiateUploadResponse>(body, "SDO initiate upload response"));
    case kScsInitiateDownload:
      return SdoResponse{SdoInitiateDownloadResponse{load_le<std::uint16_t>(body.data() + 1), body[3]}};
    case kCsAbort:
      return SdoResponse{decode_abort(body)};
    default:
      break;
  }
  return make_error(
      Errc::unsupported,
      fmt::format("SDO response: server command specifier {} (block transfer) is not supported", scs));
}

namespace {

Result<Bytes> wrap_sdo(Result<Bytes> body, CoeService service, std::uint8_t counter, std::uint16_t address) {
  if (!body) {
    return body.error();
  }
  MailboxHeader h;
  h.address = address;
  h.counter = counter;
  return encode_coe(h, CoeHeader{0, service}, *body);
}

}  // namespace

Result<Bytes> make_sdo_request(const SdoRequest& request, std::uint8_t counter, std::uint16_t address) {
  return wrap_sdo(encode_sdo_request(request), CoeService::SdoRequest, counter, address);
}

Result<Bytes> make_sdo_response(const SdoResponse& response, std::uint8_t counter, std::uint16_t address) {
  // Abort SDO Transfer is an SDO request whichever side sends it (ETG.1000.6
  // §5.6.2.7.1, CoE service 2): masters and Wireshark look for it there.
  const auto service =
      std::holds_alternative<SdoAbort>(response) ? CoeService::SdoRequest : CoeService::SdoResponse;
  return wrap_sdo(encode_sdo_response(response), service, counter, address);
}

Error sdo_abort_error(const SdoAbort& abort, std::string_view context, Errc errc) {
  return Error{errc, fmt::format("{}: {}", context, describe(abort)),
               ProtocolCode{kSdoAbortTable, abort.code}};
}

std::string describe(const SdoAbort& abort) {
  return fmt::format("SDO abort 0x{:08X} ({}) at 0x{:04X}:{:02X}", abort.code,
                     describe(static_cast<SdoAbortCode>(abort.code)), abort.index, abort.subindex);
}

}  // namespace sf::ethercat
