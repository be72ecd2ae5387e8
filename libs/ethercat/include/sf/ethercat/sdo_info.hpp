// SDO Information service (ETG.1000.6 §5.6.3, CoE service 8): how a client
// reads a slave's object dictionary without knowing it beforehand.
//   Get OD List            which objects a list (all, RxPDO/TxPDO mappable, ...) holds
//   Get Object Description data type, object code, highest subindex, name of an object
//   Get Entry Description  data type, bit length, access rights, name of an entry
//   SDO Info Error         the server's refusal, with an SDO abort code
// Every message is the CoE header, a 4-byte SDO Info header (§5.6.3.2: byte 0
// bits 6:0 opcode, bit 7 "incomplete"; byte 1 reserved; bytes 2–3 fragments
// left) and the service data. A response larger than the mailbox travels as
// several messages: the service data is cut into pieces, every piece but the
// last has "incomplete" set, and "fragments left" counts down to 0; the
// server sends them one after the other without being asked again.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat {

inline constexpr std::size_t kSdoInfoHeaderSize = 4;

enum class SdoInfoOpCode : std::uint8_t {
  GetOdListRequest = 1,
  GetOdListResponse = 2,
  GetObjectDescriptionRequest = 3,
  GetObjectDescriptionResponse = 4,
  GetEntryDescriptionRequest = 5,
  GetEntryDescriptionResponse = 6,
  ErrorRequest = 7,
};

struct SdoInfoHeader {
  std::uint8_t opcode = 0;  // SdoInfoOpCode, kept raw: unknown values must be answered
  bool incomplete = false;
  std::uint16_t fragments_left = 0;

  [[nodiscard]] std::array<std::uint8_t, kSdoInfoHeaderSize> encode() const;
  static Result<SdoInfoHeader> decode(ByteSpan body);
};

// Get OD List (§5.6.3.3). List 0 answers with the lengths of lists 1–5.
enum class OdListType : std::uint16_t {
  Lengths = 0,
  All = 1,
  RxPdoMappable = 2,
  TxPdoMappable = 3,
  StoredForReplacement = 4,
  StartupParameters = 5,
};
inline constexpr std::uint16_t kOdListTypeMax = 5;

struct OdListRequest {
  OdListType list_type = OdListType::All;
  bool operator==(const OdListRequest&) const = default;
};
struct OdListResponse {
  OdListType list_type = OdListType::All;
  std::vector<std::uint16_t> indices;  // list 0: the lengths of lists 1–5
  bool operator==(const OdListResponse&) const = default;
};

// Get Object Description (§5.6.3.5).
struct ObjectDescriptionRequest {
  std::uint16_t index = 0;
  bool operator==(const ObjectDescriptionRequest&) const = default;
};
struct ObjectDescription {
  std::uint16_t index = 0;
  std::uint16_t data_type = 0;    // ETG.1000.6 Table 64 (0x0007 UNSIGNED32, ...)
  std::uint8_t max_subindex = 0;  // highest subindex of an ARRAY/RECORD, 0 for a VAR
  std::uint8_t object_code = 0;   // 7 VAR, 8 ARRAY, 9 RECORD
  std::string name;
  bool operator==(const ObjectDescription&) const = default;
};

// Get Entry Description (§5.6.3.6). Value info bits ask for optional data
// that then precedes the name: unit type, default, minimum, maximum.
namespace value_info {
inline constexpr std::uint8_t kUnitType = 0x08;
inline constexpr std::uint8_t kDefault = 0x10;
inline constexpr std::uint8_t kMinimum = 0x20;
inline constexpr std::uint8_t kMaximum = 0x40;
}  // namespace value_info

struct EntryDescriptionRequest {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t value_info = 0;
  bool operator==(const EntryDescriptionRequest&) const = default;
};
struct EntryDescription {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t value_info = 0;  // which optional data the response carries
  std::uint16_t data_type = 0;
  std::uint16_t bit_length = 0;
  std::uint16_t object_access = 0;  // Table 49: read/write per state, RxPDO/TxPDO mappable
  Bytes values;                     // the optional data value_info announces, undecoded
  std::string name;
  bool operator==(const EntryDescription&) const = default;
};

// SDO Info Error (§5.6.3.7): an SDO abort code.
struct SdoInfoError {
  std::uint32_t code = 0;
  bool operator==(const SdoInfoError&) const = default;
};

using SdoInfoMessage =
    std::variant<OdListRequest, OdListResponse, ObjectDescriptionRequest, ObjectDescription,
                 EntryDescriptionRequest, EntryDescription, SdoInfoError>;

SdoInfoOpCode opcode_of(const SdoInfoMessage& message);
// The service data (what follows the SDO Info header).
Bytes encode_sdo_info_data(const SdoInfoMessage& message);
// Decodes reassembled service data of a message with that opcode.
Result<SdoInfoMessage> decode_sdo_info_data(std::uint8_t opcode, ByteSpan data);

// The CoE bodies (SDO Info header + piece of service data, after the CoE
// header) carrying `message` in a mailbox of `mailbox_size` bytes.
std::vector<Bytes> sdo_info_fragments(const SdoInfoMessage& message, std::size_t mailbox_size);
// A complete mailbox message (for requests, which always fit one).
Bytes make_sdo_info(const SdoInfoMessage& message, std::uint8_t counter, std::uint16_t address = 0);

// Collects the fragments of one SDO Info response (client side).
class SdoInfoReassembly {
 public:
  // Adds the CoE body of the next message; the whole message once its last
  // fragment came, nullopt while more are to come. Fragments that do not
  // continue the response (other opcode, fragments left not counting down)
  // and oversized totals are errors.
  Result<std::optional<SdoInfoMessage>> add(ByteSpan body);

 private:
  Result<std::optional<SdoInfoMessage>> add_fragment(ByteSpan body);

  std::optional<SdoInfoHeader> first_;
  std::uint16_t expected_left_ = 0;
  Bytes data_;
};

// Basic data types (ETG.1000.6 Table 64) by number.
namespace data_type {
inline constexpr std::uint16_t kBoolean = 0x0001;
inline constexpr std::uint16_t kInteger8 = 0x0002;
inline constexpr std::uint16_t kInteger16 = 0x0003;
inline constexpr std::uint16_t kInteger32 = 0x0004;
inline constexpr std::uint16_t kUnsigned8 = 0x0005;
inline constexpr std::uint16_t kUnsigned16 = 0x0006;
inline constexpr std::uint16_t kUnsigned32 = 0x0007;
inline constexpr std::uint16_t kReal32 = 0x0008;
inline constexpr std::uint16_t kVisibleString = 0x0009;
inline constexpr std::uint16_t kOctetString = 0x000A;
inline constexpr std::uint16_t kReal64 = 0x0011;
inline constexpr std::uint16_t kInteger64 = 0x0015;
inline constexpr std::uint16_t kUnsigned64 = 0x001B;
}  // namespace data_type

// "UNSIGNED32", "VISIBLE_STRING", ... ; "0x0123" for others.
std::string data_type_name(std::uint16_t data_type);
// "VAR", "ARRAY", "RECORD".
std::string object_code_name(std::uint8_t object_code);
// "rw", "ro", "rw (PREOP)", ... plus "RxPDO"/"TxPDO" when mappable.
std::string access_text(std::uint16_t object_access);

// A value of a basic type as text and back: integers in decimal, REAL32/64
// as numbers, VISIBLE_STRING as text, everything else as hex bytes.
std::string format_value(std::uint16_t data_type, ByteSpan value);
Result<Bytes> parse_value(std::uint16_t data_type, std::string_view text);
// Short type names for a command line: u8 u16 u32 u64 i8 i16 i32 i64 bool
// f32 f64 string hex (hex = OCTET_STRING).
Result<std::uint16_t> data_type_from_name(std::string_view name);

}  // namespace sf::ethercat
