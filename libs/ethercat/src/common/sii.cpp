// SII EEPROM image: fixed area (ETG.1000.6 §5.4 Table 16, ETG.2010 Table 2)
// and categories (ETG.2010 §2.3–2.11). Strings are referenced by 1-based
// index into the Strings category; index 0 means "no string".
#include "sf/ethercat/sii.hpp"

#include <algorithm>
#include <numeric>

#include <fmt/format.h>

namespace sf::ethercat {
namespace {

constexpr std::size_t kCategoryHeaderSize = 4;  // type u16, size in words u16
constexpr std::size_t kGeneralSize = 32;        // ETG.2010 Table 4
constexpr std::size_t kGeneralMinSize = 16;     // through CurrentOnEBus and the duplicate group index
constexpr std::size_t kSyncManagerEntrySize = 8;
constexpr std::size_t kPdoHeaderSize = 8;
constexpr std::size_t kPdoEntrySize = 8;
constexpr std::size_t kDcEntrySize = 24;
constexpr std::uint8_t kFmmuPadding = 0xFF;  // "not used"; pads the category to a word
// Word addresses are 16 bits: no image is larger than 64 Ki words.
constexpr std::size_t kMaxImageBytes = 2 * 0x10000;
// Words 0x1D–0x3D between the mailbox protocol word and the size word are reserved.
constexpr std::size_t kReservedTailBytes = 2U * (sii::kSize - sii::kMailboxProtocol - 1U);

// --- encoding ---------------------------------------------------------------

// Builds the string table: the given strings first, then new names in order of use.
class StringTable {
 public:
  explicit StringTable(const std::vector<std::string>& initial) : strings_(initial) {}

  std::uint8_t index(const std::string& s) {
    if (s.empty()) {
      return 0;
    }
    const auto it = std::find(strings_.begin(), strings_.end(), s);
    if (it != strings_.end()) {
      return checked(static_cast<std::size_t>(it - strings_.begin()) + 1);
    }
    strings_.push_back(s);
    return checked(strings_.size());
  }
  [[nodiscard]] const std::vector<std::string>& strings() const { return strings_; }
  [[nodiscard]] bool overflow() const { return overflow_; }

 private:
  std::uint8_t checked(std::size_t i) {
    if (i > 255) {
      overflow_ = true;
      return 0;
    }
    return static_cast<std::uint8_t>(i);
  }

  std::vector<std::string> strings_;
  bool overflow_ = false;
};

void put_category(ByteWriter& w, sii::Category type, const Bytes& data) {
  const std::size_t padded = data.size() + (data.size() % 2);
  w.u16(static_cast<std::uint16_t>(type));
  w.u16(static_cast<std::uint16_t>(padded / 2));
  w.bytes(data);
  w.zeros(padded - data.size());
}

void put_fixed_area(ByteWriter& w, const SiiInfo& info) {
  const std::size_t start = w.size();
  w.u16(info.pdi_control);
  w.u16(info.pdi_configuration);
  w.u16(info.sync_impulse_length);
  w.u16(info.pdi_configuration2);
  w.u16(info.station_alias);
  w.zeros(4);  // words 5–6 reserved
  w.u16(sii::checksum(ByteSpan(w.data()).subspan(start, 14)));
  w.u32(info.identity.vendor_id);
  w.u32(info.identity.product_code);
  w.u32(info.identity.revision);
  w.u32(info.identity.serial);
  w.zeros(8);  // words 0x10–0x13 reserved (formerly delays)
  for (const SiiMailbox* m : {&info.bootstrap_mailbox, &info.standard_mailbox}) {
    w.u16(m->rx_offset);
    w.u16(m->rx_size);
    w.u16(m->tx_offset);
    w.u16(m->tx_size);
  }
  w.u16(info.mailbox_protocols);
  w.zeros(kReservedTailBytes);
  w.u16(info.size);
  w.u16(info.version);
}

Bytes general_bytes(const SiiGeneral& g, StringTable& strings) {
  // The name takes the first free string: masters that do not follow NameIdx
  // (SOEM, KickCAT) show string 1 as the slave's name (ETG.2010 §2.3 Table 5).
  const std::uint8_t name = strings.index(g.name);
  const std::uint8_t order = strings.index(g.order);
  const std::uint8_t group = strings.index(g.group);
  const std::uint8_t image = strings.index(g.image);
  Bytes out;
  ByteWriter w(out);
  w.u8(group);
  w.u8(image);
  w.u8(order);
  w.u8(name);
  w.u8(0);  // reserved
  w.u8(g.coe_details);
  w.u8(g.foe_details);
  w.u8(g.eoe_details);
  w.u8(g.soe_channels);
  w.u8(g.ds402_channels);
  w.u8(g.sysman_class);
  w.u8(g.flags);
  w.i16(g.current_on_ebus);
  w.u8(group);  // 0x0E: group index again, for compatibility
  w.u8(0);
  w.u16(g.physical_port);
  w.u16(g.physical_memory_address);
  w.zeros(kGeneralSize - out.size());
  return out;
}

Result<Bytes> pdo_bytes(const std::vector<SiiPdo>& pdos, StringTable& strings) {
  Bytes out;
  ByteWriter w(out);
  for (const auto& pdo : pdos) {
    if (pdo.entries.size() > 255) {
      return make_error(
          Errc::invalid_argument,
          fmt::format("SII: PDO 0x{:04X} has {} entries, at most 255 fit", pdo.index, pdo.entries.size()));
    }
    w.u16(pdo.index);
    w.u8(static_cast<std::uint8_t>(pdo.entries.size()));
    w.u8(pdo.sync_manager);
    w.u8(pdo.dc_sync);
    w.u8(strings.index(pdo.name));
    w.u16(pdo.flags);
    for (const auto& e : pdo.entries) {
      w.u16(e.index);
      w.u8(e.subindex);
      w.u8(strings.index(e.name));
      w.u8(e.data_type);
      w.u8(e.bit_length);
      w.u16(e.flags);
    }
  }
  return out;
}

Bytes dc_bytes(const std::vector<SiiDcMode>& modes, StringTable& strings) {
  Bytes out;
  ByteWriter w(out);
  for (const auto& m : modes) {
    w.u32(m.cycle_time_sync0);
    w.u32(m.shift_time_sync0);
    w.u32(m.shift_time_sync1);
    w.i16(m.sync1_cycle_factor);
    w.u16(m.assign_activate);
    w.i16(m.sync0_cycle_factor);
    w.u8(strings.index(m.name));
    w.u8(strings.index(m.description));
    w.zeros(4);  // reserved
  }
  return out;
}

Result<Bytes> strings_bytes(const std::vector<std::string>& strings) {
  if (strings.size() > 255) {
    return make_error(Errc::invalid_argument,
                      fmt::format("SII: {} strings, at most 255 fit", strings.size()));
  }
  Bytes out;
  ByteWriter w(out);
  w.u8(static_cast<std::uint8_t>(strings.size()));
  for (const auto& s : strings) {
    if (s.size() > 255) {
      return make_error(
          Errc::invalid_argument,
          fmt::format("SII: string \"{}...\" of {} bytes, at most 255 fit", s.substr(0, 16), s.size()));
    }
    w.u8(static_cast<std::uint8_t>(s.size()));
    w.bytes(ByteSpan(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));  // NOLINT
  }
  return out;
}

// --- parsing ----------------------------------------------------------------

struct RawCategory {
  std::uint16_t type;
  std::size_t offset;  // of the category header, for error messages
  ByteSpan data;
};

std::string category_name(std::uint16_t type) {
  switch (static_cast<sii::Category>(type)) {
    case sii::Category::Strings:
      return "Strings";
    case sii::Category::General:
      return "General";
    case sii::Category::Fmmu:
      return "FMMU";
    case sii::Category::SyncM:
      return "SyncM";
    case sii::Category::TxPdo:
      return "TxPDO";
    case sii::Category::RxPdo:
      return "RxPDO";
    case sii::Category::Dc:
      return "DC";
    default:
      return fmt::format("category {}", type);
  }
}

Error truncated(const RawCategory& c, std::string_view detail) {
  return make_error(Errc::malformed, fmt::format("SII {} category at byte 0x{:X}: {}", category_name(c.type),
                                                 c.offset, detail));
}

// Splits the category area into categories. A category that runs past the
// data is an error; running out of data between categories is a partial read.
Result<std::vector<RawCategory>> split_categories(ByteSpan eeprom) {
  std::vector<RawCategory> out;
  std::size_t pos = sii::kFixedAreaBytes;
  while (eeprom.size() - pos >= 2) {
    const auto type = load_le<std::uint16_t>(eeprom.data() + pos);
    if (type == static_cast<std::uint16_t>(sii::Category::End)) {
      break;
    }
    if (eeprom.size() - pos < kCategoryHeaderSize) {
      return make_error(Errc::malformed, fmt::format("SII {} category at byte 0x{:X}: header truncated",
                                                     category_name(type), pos));
    }
    const std::size_t size = 2U * load_le<std::uint16_t>(eeprom.data() + pos + 2);
    if (size > eeprom.size() - pos - kCategoryHeaderSize) {
      return make_error(
          Errc::malformed,
          fmt::format("SII {} category at byte 0x{:X}: {} bytes declared, {} available", category_name(type),
                      pos, size, eeprom.size() - pos - kCategoryHeaderSize));
    }
    out.push_back({type, pos, eeprom.subspan(pos + kCategoryHeaderSize, size)});
    pos += kCategoryHeaderSize + size;
  }
  return out;
}

Result<std::vector<std::string>> parse_strings(const RawCategory& c) {
  ByteReader r(c.data);
  const std::size_t count = r.u8();
  std::vector<std::string> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t len = r.u8();
    const ByteSpan s = r.bytes(len);
    if (!r.ok()) {
      return truncated(c, fmt::format("string {} of {} runs past the category", i + 1, count));
    }
    out.emplace_back(s.begin(), s.end());
  }
  if (!r.ok()) {
    return truncated(c, "empty category (no string count)");
  }
  return out;
}

class StringLookup {
 public:
  explicit StringLookup(const std::vector<std::string>& s) : strings_(s) {}
  // Tolerant: a dangling index (a known fault of some devices) reads as "".
  [[nodiscard]] std::string operator()(std::uint8_t index) const {
    return index == 0 || index > strings_.size() ? std::string{} : strings_[index - 1U];
  }

 private:
  const std::vector<std::string>& strings_;
};

Result<SiiGeneral> parse_general(const RawCategory& c, const StringLookup& str) {
  if (c.data.size() < kGeneralMinSize) {
    return truncated(c, fmt::format("{} bytes, at least {} expected", c.data.size(), kGeneralMinSize));
  }
  ByteReader r(c.data);
  SiiGeneral g;
  g.group = str(r.u8());
  g.image = str(r.u8());
  g.order = str(r.u8());
  g.name = str(r.u8());
  r.skip(1);
  g.coe_details = r.u8();
  g.foe_details = r.u8();
  g.eoe_details = r.u8();
  g.soe_channels = r.u8();
  g.ds402_channels = r.u8();
  g.sysman_class = r.u8();
  g.flags = r.u8();
  g.current_on_ebus = r.i16();
  r.skip(2);                 // group index duplicate, reserved
  if (r.remaining() >= 4) {  // older devices end the category here
    g.physical_port = r.u16();
    g.physical_memory_address = r.u16();
  }
  return g;
}

std::vector<SiiFmmuUsage> parse_fmmus(const RawCategory& c) {
  std::vector<SiiFmmuUsage> out;
  for (const std::uint8_t b : c.data) {
    out.push_back(b == kFmmuPadding ? SiiFmmuUsage::unused : static_cast<SiiFmmuUsage>(b));
  }
  // Trailing 0xFF bytes are padding or "not used" entries: drop them.
  std::size_t keep = c.data.size();
  while (keep > 0 && c.data[keep - 1] == kFmmuPadding) {
    --keep;
  }
  out.resize(keep);
  return out;
}

Result<std::vector<SiiSyncManager>> parse_sync_managers(const RawCategory& c) {
  if (c.data.size() % kSyncManagerEntrySize != 0) {
    return truncated(c,
                     fmt::format("{} bytes is not a multiple of {}", c.data.size(), kSyncManagerEntrySize));
  }
  std::vector<SiiSyncManager> out;
  ByteReader r(c.data);
  while (!r.at_end()) {
    SiiSyncManager s;
    s.start = r.u16();
    s.length = r.u16();
    s.control = r.u8();
    s.status = r.u8();
    s.enable = r.u8();
    s.type = static_cast<SiiSyncManagerType>(r.u8());
    out.push_back(s);
  }
  return out;
}

Result<std::vector<SiiPdo>> parse_pdos(const RawCategory& c, const StringLookup& str) {
  std::vector<SiiPdo> out;
  ByteReader r(c.data);
  // A category ends with at most one byte of word padding.
  while (r.remaining() >= kPdoHeaderSize) {
    SiiPdo pdo;
    pdo.index = r.u16();
    const std::size_t count = r.u8();
    pdo.sync_manager = r.u8();
    pdo.dc_sync = r.u8();
    pdo.name = str(r.u8());
    pdo.flags = r.u16();
    if (r.remaining() < count * kPdoEntrySize) {
      return truncated(c, fmt::format("PDO 0x{:04X} declares {} entries, only {} bytes follow", pdo.index,
                                      count, r.remaining()));
    }
    for (std::size_t i = 0; i < count; ++i) {
      SiiPdoEntry e;
      e.index = r.u16();
      e.subindex = r.u8();
      e.name = str(r.u8());
      e.data_type = r.u8();
      e.bit_length = r.u8();
      e.flags = r.u16();
      pdo.entries.push_back(std::move(e));
    }
    out.push_back(std::move(pdo));
  }
  if (r.remaining() != 0) {
    return truncated(c,
                     fmt::format("{} bytes left over, a PDO header needs {}", r.remaining(), kPdoHeaderSize));
  }
  return out;
}

Result<std::vector<SiiDcMode>> parse_dc(const RawCategory& c, const StringLookup& str) {
  if (c.data.size() % kDcEntrySize != 0) {
    return truncated(c, fmt::format("{} bytes is not a multiple of {}", c.data.size(), kDcEntrySize));
  }
  std::vector<SiiDcMode> out;
  ByteReader r(c.data);
  while (!r.at_end()) {
    SiiDcMode m;
    m.cycle_time_sync0 = r.u32();
    m.shift_time_sync0 = r.u32();
    m.shift_time_sync1 = r.u32();
    m.sync1_cycle_factor = r.i16();
    m.assign_activate = r.u16();
    m.sync0_cycle_factor = r.i16();
    m.name = str(r.u8());
    m.description = str(r.u8());
    r.skip(4);
    out.push_back(std::move(m));
  }
  return out;
}

void parse_fixed_area(ByteReader& r, SiiInfo& info) {
  info.pdi_control = r.u16();
  info.pdi_configuration = r.u16();
  info.sync_impulse_length = r.u16();
  info.pdi_configuration2 = r.u16();
  info.station_alias = r.u16();
  r.skip(6);  // reserved words 5–6, checksum (verified separately)
  info.identity.vendor_id = r.u32();
  info.identity.product_code = r.u32();
  info.identity.revision = r.u32();
  info.identity.serial = r.u32();
  r.skip(8);
  for (SiiMailbox* m : {&info.bootstrap_mailbox, &info.standard_mailbox}) {
    m->rx_offset = r.u16();
    m->rx_size = r.u16();
    m->tx_offset = r.u16();
    m->tx_size = r.u16();
  }
  info.mailbox_protocols = r.u16();
  r.skip(kReservedTailBytes);
  info.size = r.u16();
  info.version = r.u16();
}

// Applies one category (other than Strings) to info.
Status apply_category(const RawCategory& c, const StringLookup& str, SiiInfo& info) {
  auto append = [](auto& to, auto&& result) -> Status {
    if (!result) {
      return result.error();
    }
    to.insert(to.end(), result->begin(), result->end());
    return {};
  };
  switch (static_cast<sii::Category>(c.type)) {
    case sii::Category::General: {
      auto g = parse_general(c, str);
      if (!g) {
        return g.error();
      }
      info.general = std::move(*g);
      return {};
    }
    case sii::Category::Fmmu:
      info.fmmus = parse_fmmus(c);
      return {};
    case sii::Category::SyncM:
      return append(info.sync_managers, parse_sync_managers(c));
    case sii::Category::TxPdo:
      return append(info.tx_pdos, parse_pdos(c, str));
    case sii::Category::RxPdo:
      return append(info.rx_pdos, parse_pdos(c, str));
    case sii::Category::Dc:
      return append(info.dc_modes, parse_dc(c, str));
    default:
      return {};  // unknown, vendor-specific, Nop, DataTypes...: skipped
  }
}

std::uint16_t size_field_for(std::size_t image_bytes) {
  // Word 0x3E: EEPROM size in KiBit − 1; 1 KiBit = 128 bytes.
  const std::size_t kibit = (image_bytes + 127) / 128;
  return static_cast<std::uint16_t>(kibit == 0 ? 0 : kibit - 1);
}

}  // namespace

std::uint8_t sii::checksum(ByteSpan first_14_bytes) {
  std::uint8_t crc = 0xFF;
  for (const std::uint8_t byte : first_14_bytes.first(std::min<std::size_t>(14, first_14_bytes.size()))) {
    crc = static_cast<std::uint8_t>(crc ^ byte);
    for (int bit = 0; bit < 8; ++bit) {
      const unsigned shifted = static_cast<unsigned>(crc) << 1U;
      crc = static_cast<std::uint8_t>((crc & 0x80U) != 0 ? shifted ^ 0x07U : shifted);
    }
  }
  return crc;
}

std::size_t SiiPdo::bit_length() const {
  return std::accumulate(entries.begin(), entries.end(), std::size_t{0},
                         [](std::size_t sum, const SiiPdoEntry& e) { return sum + e.bit_length; });
}

Result<Bytes> encode_sii(const SiiInfo& info) {
  StringTable strings(info.strings);
  // Categories that reference strings are built first, so the table is complete.
  const Bytes general = info.general ? general_bytes(*info.general, strings) : Bytes{};
  auto tx = pdo_bytes(info.tx_pdos, strings);
  auto rx = pdo_bytes(info.rx_pdos, strings);
  if (!tx || !rx) {
    return tx ? rx.error() : tx.error();
  }
  const Bytes dc = dc_bytes(info.dc_modes, strings);
  auto string_data = strings_bytes(strings.strings());
  if (!string_data || strings.overflow()) {
    return string_data ? make_error(Errc::invalid_argument, "SII: more than 255 strings")
                       : string_data.error();
  }

  Bytes out;
  ByteWriter w(out);
  put_fixed_area(w, info);
  if (!strings.strings().empty()) {
    put_category(w, sii::Category::Strings, *string_data);
  }
  if (info.general) {
    put_category(w, sii::Category::General, general);
  }
  if (!info.fmmus.empty()) {
    Bytes fmmu;
    for (const auto u : info.fmmus) {
      fmmu.push_back(static_cast<std::uint8_t>(u));
    }
    if (fmmu.size() % 2 != 0) {
      fmmu.push_back(kFmmuPadding);
    }
    put_category(w, sii::Category::Fmmu, fmmu);
  }
  if (!info.sync_managers.empty()) {
    Bytes sm;
    ByteWriter s(sm);
    for (const auto& m : info.sync_managers) {
      s.u16(m.start);
      s.u16(m.length);
      s.u8(m.control);
      s.u8(m.status);
      s.u8(m.enable);
      s.u8(static_cast<std::uint8_t>(m.type));
    }
    put_category(w, sii::Category::SyncM, sm);
  }
  if (!info.tx_pdos.empty()) {
    put_category(w, sii::Category::TxPdo, *tx);
  }
  if (!info.rx_pdos.empty()) {
    put_category(w, sii::Category::RxPdo, *rx);
  }
  if (!info.dc_modes.empty()) {
    put_category(w, sii::Category::Dc, dc);
  }
  w.u16(static_cast<std::uint16_t>(sii::Category::End));
  w.u16(0xFFFF);  // erased EEPROM after the End marker
  if (out.size() > kMaxImageBytes) {
    return make_error(Errc::limit_exceeded,
                      fmt::format("SII image of {} bytes exceeds 64 Ki words", out.size()));
  }
  if (info.size == 0) {
    store_le<std::uint16_t>(out.data() + 2U * sii::kSize, size_field_for(out.size()));
  }
  return out;
}

Result<SiiInfo> parse_sii(ByteSpan eeprom, SiiParseOptions options) {
  if (eeprom.size() < sii::kFixedAreaBytes) {
    return make_error(Errc::malformed,
                      fmt::format("SII image of {} bytes is shorter than the {}-byte fixed area",
                                  eeprom.size(), sii::kFixedAreaBytes));
  }
  const std::uint8_t crc = sii::checksum(eeprom.first(14));
  const std::uint8_t stored = eeprom[2 * sii::kChecksum];
  if (options.verify_checksum && crc != stored) {
    return make_error(
        Errc::malformed,
        fmt::format("SII checksum 0x{:02X} in word 7 does not match 0x{:02X} of words 0-6", stored, crc));
  }
  SiiInfo info;
  ByteReader r(eeprom.first(sii::kFixedAreaBytes));
  parse_fixed_area(r, info);

  auto categories = split_categories(eeprom);
  if (!categories) {
    return categories.error();
  }
  for (const auto& c : *categories) {
    if (c.type == static_cast<std::uint16_t>(sii::Category::Strings)) {
      auto s = parse_strings(c);
      if (!s) {
        return s.error();
      }
      info.strings.insert(info.strings.end(), s->begin(), s->end());
    }
  }
  const StringLookup lookup(info.strings);
  for (const auto& c : *categories) {
    SF_TRY(apply_category(c, lookup, info));
  }
  return info;
}

Result<std::optional<std::size_t>> sii_image_length(ByteSpan prefix) {
  std::size_t pos = sii::kFixedAreaBytes;
  while (true) {
    if (pos > kMaxImageBytes) {
      return make_error(Errc::malformed,
                        fmt::format("SII category chain runs past 64 Ki words without an End category"));
    }
    if (prefix.size() < pos + 2) {
      return std::optional<std::size_t>{};
    }
    const auto type = load_le<std::uint16_t>(prefix.data() + pos);
    if (type == static_cast<std::uint16_t>(sii::Category::End)) {
      return std::optional<std::size_t>{pos + 2};
    }
    if (prefix.size() < pos + kCategoryHeaderSize) {
      return std::optional<std::size_t>{};
    }
    pos += kCategoryHeaderSize + 2U * load_le<std::uint16_t>(prefix.data() + pos + 2);
  }
}

}  // namespace sf::ethercat
