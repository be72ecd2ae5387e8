// Mailbox and CoE/SDO codecs, shared by the slave's SDO server and the master's
// SDO client.
//   mailbox header:     ETG.1000.4 §5.6 (Table 29), 6 bytes
//   mailbox error:      ETG.1000.4 §5.6, type 0 (Table 30)
//   CoE header:         ETG.1000.6 §5.6.1, 2 bytes
//   SDO services:       ETG.1000.6 §5.6.2 (CiA 301 SDO protocol, mailbox form)
//   emergency:          ETG.1000.6 §5.6.4
// A mailbox message occupies the start of a mailbox SyncManager buffer; the
// header's length field says how many data bytes follow, the rest is padding.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat {

// --------------------------------------------------------------------------
// Mailbox header
// --------------------------------------------------------------------------

inline constexpr std::size_t kMailboxHeaderSize = 6;

enum class MailboxType : std::uint8_t { Err = 0, AoE = 1, EoE = 2, CoE = 3, FoE = 4, SoE = 5, VoE = 15 };
std::string_view to_string(MailboxType t);

struct MailboxHeader {
  std::uint16_t length = 0;             // bytes of mailbox data after this header
  std::uint16_t address = 0;            // station address of the originator (0 = master)
  std::uint8_t channel = 0;             // 6 bits, reserved (0)
  std::uint8_t priority = 0;            // 2 bits
  MailboxType type = MailboxType::CoE;  // 4 bits; unknown values are kept as raw numbers
  std::uint8_t counter = 0;             // 3 bits; 1..7 in use, 0 = no repeat detection

  [[nodiscard]] std::array<std::uint8_t, kMailboxHeaderSize> encode() const;
  // Decodes the 6 header bytes (does not check `length` against anything).
  static Result<MailboxHeader> decode(ByteSpan bytes);
  bool operator==(const MailboxHeader&) const = default;
};

// The next mailbox counter after c: 1, 2, ... 7, 1, ... (0 is never used for a
// new message, ETG.1000.4 §5.6).
constexpr std::uint8_t next_mailbox_counter(std::uint8_t c) {
  return static_cast<std::uint8_t>(c >= 7 ? 1 : c + 1);
}

// A decoded mailbox message; `data` views the caller's buffer.
struct MailboxMessage {
  MailboxHeader header;
  ByteSpan data;
};

// Header (with length = data.size()) followed by data.
Bytes encode_mailbox(MailboxHeader header, ByteSpan data);
// Decodes a mailbox buffer: the header and exactly header.length data bytes;
// trailing bytes (the unused rest of the SyncManager buffer) are ignored.
Result<MailboxMessage> decode_mailbox(ByteSpan buffer);

// Mailbox error reply (type 0): Type 0x0001, then a 16-bit detail code.
enum class MailboxError : std::uint16_t {
  Syntax = 0x0001,
  UnsupportedProtocol = 0x0002,
  InvalidChannel = 0x0003,
  ServiceNotSupported = 0x0004,
  InvalidHeader = 0x0005,
  SizeTooShort = 0x0006,
  NoMoreMemory = 0x0007,
  InvalidSize = 0x0008,
  ServiceInWork = 0x0009,
};
std::string_view describe(MailboxError e);
inline constexpr std::uint16_t kMailboxErrorServiceType = 0x0001;
// A complete mailbox message of type Err.
Bytes encode_mailbox_error(MailboxError error, std::uint8_t counter = 0, std::uint16_t address = 0);
// Decodes the 4 data bytes of a type-Err mailbox message.
Result<MailboxError> decode_mailbox_error(ByteSpan data);

// --------------------------------------------------------------------------
// CoE header (ETG.1000.6 §5.6.1): number bits 8:0, reserved 11:9, service 15:12
// --------------------------------------------------------------------------

inline constexpr std::size_t kCoeHeaderSize = 2;

enum class CoeService : std::uint8_t {
  Emergency = 1,
  SdoRequest = 2,
  SdoResponse = 3,
  TxPdo = 4,
  RxPdo = 5,
  TxPdoRemoteRequest = 6,
  RxPdoRemoteRequest = 7,
  SdoInformation = 8,
};
std::string_view to_string(CoeService s);

struct CoeHeader {
  std::uint16_t number = 0;  // 9 bits; PDO number for TxPdo/RxPdo, 0 otherwise
  CoeService service = CoeService::SdoRequest;

  [[nodiscard]] std::uint16_t encode() const;
  static Result<CoeHeader> decode(std::uint16_t value);  // service 0 or > 8 is rejected
  bool operator==(const CoeHeader&) const = default;
};

// A decoded CoE mailbox message; `body` (what follows the CoE header) views
// the caller's buffer.
struct CoeMessage {
  MailboxHeader mailbox;
  CoeHeader coe;
  ByteSpan body;
};
// Mailbox header (type CoE) + CoE header + body.
Bytes encode_coe(MailboxHeader mailbox, CoeHeader coe, ByteSpan body);
// Decodes a mailbox buffer that must hold a CoE message.
Result<CoeMessage> decode_coe(ByteSpan buffer);

// Emergency (ETG.1000.6 §5.6.4): error code, error register, 5 bytes of data.
struct CoeEmergency {
  std::uint16_t error_code = 0;
  std::uint8_t error_register = 0;
  std::array<std::uint8_t, 5> data{};

  [[nodiscard]] Bytes encode() const;  // 8 body bytes (after the CoE header)
  static Result<CoeEmergency> decode(ByteSpan body);
  bool operator==(const CoeEmergency&) const = default;
};

// --------------------------------------------------------------------------
// SDO (ETG.1000.6 §5.6.2). Every SDO body starts with a command byte whose
// bits 7:5 are the command specifier; index/subindex follow for initiate and
// abort services. The "body" below is what follows the CoE header.
// --------------------------------------------------------------------------

// Smallest SDO body: command byte + 7 bytes (mailbox length 10).
inline constexpr std::size_t kSdoBodyMinSize = 8;
// Smallest segment payload on the wire; shorter data is padded and the
// "seg data size" field says how many of the 7 bytes are unused.
inline constexpr std::size_t kSdoMinSegmentData = 7;
// Bytes of mailbox SyncManager consumed before SDO data begins.
inline constexpr std::size_t kSdoInitiateOverhead = kMailboxHeaderSize + kCoeHeaderSize + 8;  // 16
inline constexpr std::size_t kSdoSegmentOverhead = kMailboxHeaderSize + kCoeHeaderSize + 1;   // 9

// Most data bytes that fit in a normal initiate download request / upload
// response, and in one segment, for a mailbox of mailbox_size bytes.
constexpr std::size_t sdo_initiate_capacity(std::size_t mailbox_size) {
  return mailbox_size > kSdoInitiateOverhead ? mailbox_size - kSdoInitiateOverhead : 0;
}
constexpr std::size_t sdo_segment_capacity(std::size_t mailbox_size) {
  return mailbox_size > kSdoSegmentOverhead ? mailbox_size - kSdoSegmentOverhead : 0;
}

// Client → server, command specifier 1. Expedited: 1–4 bytes inline, the
// size indicator and "data set size" say how many. Normal: a 4-byte complete
// size, then as much data as fits; the rest follows in download segments.
struct SdoInitiateDownloadRequest {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  bool complete_access = false;
  bool expedited = true;
  bool size_indicated = true;       // expedited only: false → 4 bytes, size unspecified
  std::uint32_t complete_size = 0;  // normal: total bytes of the object; expedited: data.size()
  Bytes data;

  // The usual choice for writing `object`: expedited if it has 1–4 bytes,
  // otherwise normal with complete_size = object.size() and the first
  // min(capacity, size) bytes as data (capacity = sdo_initiate_capacity(mailbox
  // size)); the client sends object[data.size()..] in download segments.
  static SdoInitiateDownloadRequest make(std::uint16_t index, std::uint8_t subindex, ByteSpan object,
                                         std::size_t capacity, bool complete_access = false);
  bool operator==(const SdoInitiateDownloadRequest&) const = default;
};

// Server → client, command specifier 3; no data.
struct SdoInitiateDownloadResponse {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  bool operator==(const SdoInitiateDownloadResponse&) const = default;
};

// Client → server, command specifier 0. `last` is the c bit (no more segments).
struct SdoDownloadSegmentRequest {
  bool toggle = false;
  bool last = false;
  Bytes data;  // on the wire at least 7 bytes; shorter is padded
  bool operator==(const SdoDownloadSegmentRequest&) const = default;
};

// Server → client, command specifier 1.
struct SdoDownloadSegmentResponse {
  bool toggle = false;
  bool operator==(const SdoDownloadSegmentResponse&) const = default;
};

// Client → server, command specifier 2.
struct SdoInitiateUploadRequest {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  bool complete_access = false;
  bool operator==(const SdoInitiateUploadRequest&) const = default;
};

// Server → client, command specifier 2; the same layout as the initiate
// download request (expedited 1–4 bytes, or complete size + first data).
struct SdoInitiateUploadResponse {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  bool complete_access = false;
  bool expedited = true;
  bool size_indicated = true;
  std::uint32_t complete_size = 0;
  Bytes data;

  // The server's answer for reading `object`, chosen as in
  // SdoInitiateDownloadRequest::make (expedited for 1–4 bytes, else normal
  // with the first min(capacity, size) bytes).
  static SdoInitiateUploadResponse make(std::uint16_t index, std::uint8_t subindex, ByteSpan object,
                                        std::size_t capacity, bool complete_access = false);
  bool operator==(const SdoInitiateUploadResponse&) const = default;
};

// Client → server, command specifier 3.
struct SdoUploadSegmentRequest {
  bool toggle = false;
  bool operator==(const SdoUploadSegmentRequest&) const = default;
};

// Server → client, command specifier 0.
struct SdoUploadSegmentResponse {
  bool toggle = false;
  bool last = false;
  Bytes data;
  bool operator==(const SdoUploadSegmentResponse&) const = default;
};

// Either direction, command specifier 4; code from sdo_abort_codes.hpp.
struct SdoAbort {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint32_t code = 0;
  bool operator==(const SdoAbort&) const = default;
};

using SdoRequest = std::variant<SdoInitiateDownloadRequest, SdoDownloadSegmentRequest,
                                SdoInitiateUploadRequest, SdoUploadSegmentRequest, SdoAbort>;
using SdoResponse = std::variant<SdoInitiateDownloadResponse, SdoDownloadSegmentResponse,
                                 SdoInitiateUploadResponse, SdoUploadSegmentResponse, SdoAbort>;

// SDO body bytes (command byte onwards, at least kSdoBodyMinSize). Fails when
// a field is out of range (expedited data of 0 or > 4 bytes, data > 2^32...).
Result<Bytes> encode_sdo_request(const SdoRequest& request);
Result<Bytes> encode_sdo_response(const SdoResponse& response);
// Decodes an SDO body (after the CoE header) sent by a client / by a server.
// Which command a byte means depends on the direction, hence two functions.
Result<SdoRequest> decode_sdo_request(ByteSpan body);
Result<SdoResponse> decode_sdo_response(ByteSpan body);

// Complete mailbox messages (mailbox header + CoE header + SDO body) for the
// common case, with the given counter and originator address. An abort goes
// under CoE service 2 (SDO request) from either side (ETG.1000.6 §5.6.2.7.1);
// every other response under service 3.
Result<Bytes> make_sdo_request(const SdoRequest& request, std::uint8_t counter, std::uint16_t address = 0);
Result<Bytes> make_sdo_response(const SdoResponse& response, std::uint8_t counter, std::uint16_t address = 0);

// "SDO abort 0x06020000 (Object does not exist in the object dictionary) at 0x1234:05".
std::string describe(const SdoAbort& abort);

// The table of an Error's protocol_code that holds an SDO abort code.
inline constexpr std::string_view kSdoAbortTable = "CoE SDO abort";
// A slave's abort as an error, `errc` (default Errc::remote) with the
// describe() text after `context` and the code kept typed.
Error sdo_abort_error(const SdoAbort& abort, std::string_view context, Errc errc = Errc::remote);

}  // namespace sf::ethercat
