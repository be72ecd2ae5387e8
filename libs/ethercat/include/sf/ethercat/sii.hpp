// Slave Information Interface (SII) EEPROM layout (ETG.1000.6 §5.4, ETG.2010).
// The EEPROM is word-addressed (16-bit words, little-endian). Words 0x00–0x3F
// are the fixed area (ESC configuration, identity, mailbox layout); from word
// 0x40 on follow categories: {type u16, size in words u16, data}, ended by
// category 0xFFFF. encode_sii() produces what an emulated slave stores;
// parse_sii() is what the master makes of what it read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat {

namespace sii {

// Word addresses of the fixed area (ETG.1000.6 Table 16 / ETG.2010 Table 2).
inline constexpr std::uint16_t kPdiControl = 0x0000;         // → ESC 0x0140
inline constexpr std::uint16_t kPdiConfiguration = 0x0001;   // → ESC 0x0150
inline constexpr std::uint16_t kSyncImpulseLength = 0x0002;  // → ESC 0x0982, 10 ns units
inline constexpr std::uint16_t kPdiConfiguration2 = 0x0003;  // → ESC 0x0152
inline constexpr std::uint16_t kStationAlias = 0x0004;       // → ESC 0x0012
inline constexpr std::uint16_t kChecksum = 0x0007;           // low byte: CRC-8 of words 0–6
inline constexpr std::uint16_t kVendorId = 0x0008;           // u32
inline constexpr std::uint16_t kProductCode = 0x000A;        // u32
inline constexpr std::uint16_t kRevisionNumber = 0x000C;     // u32
inline constexpr std::uint16_t kSerialNumber = 0x000E;       // u32
inline constexpr std::uint16_t kBootstrapRxMailboxOffset = 0x0014;
inline constexpr std::uint16_t kBootstrapRxMailboxSize = 0x0015;
inline constexpr std::uint16_t kBootstrapTxMailboxOffset = 0x0016;
inline constexpr std::uint16_t kBootstrapTxMailboxSize = 0x0017;
inline constexpr std::uint16_t kStandardRxMailboxOffset = 0x0018;  // master → slave (SM0)
inline constexpr std::uint16_t kStandardRxMailboxSize = 0x0019;
inline constexpr std::uint16_t kStandardTxMailboxOffset = 0x001A;  // slave → master (SM1)
inline constexpr std::uint16_t kStandardTxMailboxSize = 0x001B;
inline constexpr std::uint16_t kMailboxProtocol = 0x001C;  // MailboxProtocol bits
inline constexpr std::uint16_t kSize = 0x003E;             // EEPROM size in KiBit − 1
inline constexpr std::uint16_t kVersion = 0x003F;          // 1
inline constexpr std::uint16_t kFirstCategory = 0x0040;
inline constexpr std::size_t kFixedAreaBytes = 2 * kFirstCategory;  // 128

// Category types (ETG.1000.6 Table 17 / ETG.2010 Table 3). Bit 15 of the
// type marks vendor-specific categories; unknown ones are skipped.
enum class Category : std::uint16_t {
  Nop = 0,
  Strings = 10,
  DataTypes = 20,
  General = 30,
  Fmmu = 40,
  SyncM = 41,
  FmmuX = 42,
  SyncUnit = 43,
  TxPdo = 50,
  RxPdo = 51,
  Dc = 60,
  End = 0xFFFF,
};

// Mailbox protocols supported (word 0x1C).
namespace protocol {
inline constexpr std::uint16_t kAoE = 1U << 0;
inline constexpr std::uint16_t kEoE = 1U << 1;
inline constexpr std::uint16_t kCoE = 1U << 2;
inline constexpr std::uint16_t kFoE = 1U << 3;
inline constexpr std::uint16_t kSoE = 1U << 4;
inline constexpr std::uint16_t kVoE = 1U << 5;
}  // namespace protocol

// General category CoE details bits.
namespace coe_details {
inline constexpr std::uint8_t kSdo = 1U << 0;
inline constexpr std::uint8_t kSdoInfo = 1U << 1;
inline constexpr std::uint8_t kPdoAssign = 1U << 2;
inline constexpr std::uint8_t kPdoConfiguration = 1U << 3;
inline constexpr std::uint8_t kUploadAtStartup = 1U << 4;
inline constexpr std::uint8_t kSdoCompleteAccess = 1U << 5;
}  // namespace coe_details

// CRC-8 of the ESC configuration area as ESCs check it: polynomial
// x^8 + x^2 + x + 1 (0x07), initial value 0xFF, no reflection, no final XOR,
// over the 14 bytes of words 0–6.
std::uint8_t checksum(ByteSpan first_14_bytes);

}  // namespace sii

struct SiiIdentity {
  std::uint32_t vendor_id = 0;
  std::uint32_t product_code = 0;
  std::uint32_t revision = 0;
  std::uint32_t serial = 0;
  bool operator==(const SiiIdentity&) const = default;
};

struct SiiMailbox {
  std::uint16_t rx_offset = 0;  // master → slave mailbox (SM0) physical start
  std::uint16_t rx_size = 0;
  std::uint16_t tx_offset = 0;  // slave → master mailbox (SM1)
  std::uint16_t tx_size = 0;
  [[nodiscard]] bool present() const { return rx_size != 0 && tx_size != 0; }
  bool operator==(const SiiMailbox&) const = default;
};

// General category (30), ETG.2010 Table 4 (32 bytes). Names are resolved
// from / added to the string table.
struct SiiGeneral {
  std::string group;
  std::string image;
  std::string order;
  std::string name;
  std::uint8_t coe_details = 0;  // sii::coe_details bits
  std::uint8_t foe_details = 0;
  std::uint8_t eoe_details = 0;
  std::uint8_t soe_channels = 0;
  std::uint8_t ds402_channels = 0;
  std::uint8_t sysman_class = 0;
  std::uint8_t flags = 0;  // bit0 SafeOp enabled, bit1 notLRW, bit2 MBoxDataLinkLayer, bit3 IdentALSts
  std::int16_t current_on_ebus = 0;  // mA; negative = feeding
  std::uint16_t physical_port = 0;   // 4 bits per port: 0 none, 1 MII, 3 EBUS
  std::uint16_t physical_memory_address = 0;
  bool operator==(const SiiGeneral&) const = default;
};

// FMMU category (40): one byte per FMMU.
enum class SiiFmmuUsage : std::uint8_t { unused = 0x00, outputs = 0x01, inputs = 0x02, sm_status = 0x03 };

// SyncM category (41): 8 bytes per SyncManager.
enum class SiiSyncManagerType : std::uint8_t {
  unused = 0,
  mailbox_out = 1,  // master → slave
  mailbox_in = 2,   // slave → master
  outputs = 3,      // process data master → slave
  inputs = 4,       // process data slave → master
};
struct SiiSyncManager {
  std::uint16_t start = 0;
  std::uint16_t length = 0;
  std::uint8_t control = 0;  // as ESC register +4
  std::uint8_t status = 0;   // don't care
  std::uint8_t enable = 0;   // bit0 enable, bit1 fixed content, bit2 virtual, bit3 OP only
  SiiSyncManagerType type = SiiSyncManagerType::unused;
  bool operator==(const SiiSyncManager&) const = default;
};

// TxPDO (50) / RxPDO (51) categories: 8-byte PDO header then 8 bytes per entry.
struct SiiPdoEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::string name;
  std::uint8_t data_type = 0;  // CoE data type index (0x07 = UNSIGNED32, ...)
  std::uint8_t bit_length = 0;
  std::uint16_t flags = 0;
  bool operator==(const SiiPdoEntry&) const = default;
};
struct SiiPdo {
  std::uint16_t index = 0;
  std::uint8_t sync_manager = 0;  // 0xFF = not assigned
  std::uint8_t dc_sync = 0;
  std::string name;
  std::uint16_t flags = 0;
  std::vector<SiiPdoEntry> entries;
  [[nodiscard]] std::size_t bit_length() const;
  bool operator==(const SiiPdo&) const = default;
};

// DC category (60), ETG.2010 Table 12: 24 bytes per operation mode.
struct SiiDcMode {
  std::uint32_t cycle_time_sync0 = 0;
  std::uint32_t shift_time_sync0 = 0;
  std::uint32_t shift_time_sync1 = 0;
  std::int16_t sync1_cycle_factor = 0;
  std::uint16_t assign_activate = 0;  // value for ESC 0x0980/0x0981
  std::int16_t sync0_cycle_factor = 0;
  std::string name;
  std::string description;
  bool operator==(const SiiDcMode&) const = default;
};

struct SiiInfo {
  // ESC configuration area (words 0–4), loaded by the ESC at power-up.
  std::uint16_t pdi_control = 0;
  std::uint16_t pdi_configuration = 0;
  std::uint16_t sync_impulse_length = 0;
  std::uint16_t pdi_configuration2 = 0;
  std::uint16_t station_alias = 0;

  SiiIdentity identity;
  SiiMailbox bootstrap_mailbox;
  SiiMailbox standard_mailbox;
  std::uint16_t mailbox_protocols = 0;  // sii::protocol bits
  std::uint16_t size = 0;               // EEPROM size in KiBit − 1 (word 0x3E)
  std::uint16_t version = 1;

  // The string table (1-based on the wire). parse_sii() fills it with every
  // string; encode_sii() writes it first and appends names used below that
  // are not in it yet.
  std::vector<std::string> strings;
  std::optional<SiiGeneral> general;
  std::vector<SiiFmmuUsage> fmmus;
  std::vector<SiiSyncManager> sync_managers;
  std::vector<SiiPdo> tx_pdos;
  std::vector<SiiPdo> rx_pdos;
  std::vector<SiiDcMode> dc_modes;  // empty: no DC category

  [[nodiscard]] bool supports_dc() const { return !dc_modes.empty(); }
  // Device name: the General category's name if present, else "".
  [[nodiscard]] std::string name() const { return general ? general->name : std::string{}; }
  bool operator==(const SiiInfo&) const = default;
};

// The EEPROM image: fixed area with a correct checksum, then the categories
// present (Strings, General, FMMU, SyncM, TxPDO, RxPDO, DC) and End. The
// result has an even size. Fails if a count does not fit its field (more
// than 255 strings or PDO entries, a string longer than 255 bytes).
Result<Bytes> encode_sii(const SiiInfo& info);

struct SiiParseOptions {
  bool verify_checksum = true;
};
// Parses an EEPROM image (at least the 128-byte fixed area). Unknown and
// vendor categories are skipped; a category whose size runs past the data or
// whose content is shorter than its layout is an error naming it. Reaching the
// end of the data without an End category is accepted (a partial read).
Result<SiiInfo> parse_sii(ByteSpan eeprom, SiiParseOptions options = {});

// For a master reading the EEPROM piecewise: the byte length of the image up
// to and including the End category if `prefix` already contains it, nullopt
// if more must be read, an error if the category chain is broken.
Result<std::optional<std::size_t>> sii_image_length(ByteSpan prefix);

}  // namespace sf::ethercat
