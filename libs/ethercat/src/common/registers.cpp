// Value types of the structured ESC registers: AL control/status (ET1100
// datasheet II §4, 0x0120/0x0130), FMMU (§11, 0x0600) and SyncManager (§12,
// 0x0800).
#include "sf/ethercat/registers.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

namespace sf::ethercat {
namespace {

bool iequals(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::toupper(static_cast<unsigned char>(x)) == std::toupper(static_cast<unsigned char>(y));
  });
}

}  // namespace

std::string_view to_string(AlState s) {
  switch (s) {
    case AlState::Init:
      return "INIT";
    case AlState::PreOp:
      return "PREOP";
    case AlState::Bootstrap:
      return "BOOT";
    case AlState::SafeOp:
      return "SAFEOP";
    case AlState::Op:
      return "OP";
  }
  return "INVALID";
}

std::optional<AlState> al_state_from_string(std::string_view name) {
  struct Alias {
    std::string_view name;
    AlState state;
  };
  static constexpr std::array<Alias, 9> kAliases{{{"INIT", AlState::Init},
                                                  {"PREOP", AlState::PreOp},
                                                  {"PRE-OP", AlState::PreOp},
                                                  {"BOOT", AlState::Bootstrap},
                                                  {"BOOTSTRAP", AlState::Bootstrap},
                                                  {"SAFEOP", AlState::SafeOp},
                                                  {"SAFE-OP", AlState::SafeOp},
                                                  {"OP", AlState::Op},
                                                  {"OPERATIONAL", AlState::Op}}};
  for (const auto& a : kAliases) {
    if (iequals(a.name, name)) {
      return a.state;
    }
  }
  return std::nullopt;
}

std::optional<AlState> al_state_from_bits(std::uint16_t value) {
  switch (value & reg::kAlStateMask) {
    case 1:
      return AlState::Init;
    case 2:
      return AlState::PreOp;
    case 3:
      return AlState::Bootstrap;
    case 4:
      return AlState::SafeOp;
    case 8:
      return AlState::Op;
    default:
      return std::nullopt;
  }
}

std::uint16_t AlStatus::encode() const {
  return static_cast<std::uint16_t>((state_bits & reg::kAlStateMask) | (error ? reg::kAlErrorFlag : 0U) |
                                    (id_loaded ? reg::kAlDeviceIdentification : 0U));
}

AlStatus AlStatus::decode(std::uint16_t value) {
  return AlStatus{static_cast<std::uint8_t>(value & reg::kAlStateMask), (value & reg::kAlErrorFlag) != 0,
                  (value & reg::kAlDeviceIdentification) != 0};
}

std::string AlStatus::to_string() const {
  const auto s = state();
  std::string out = s ? std::string(ethercat::to_string(*s)) : fmt::format("0x{:X} (invalid)", state_bits);
  if (error) {
    out += " + ERROR";
  }
  return out;
}

std::uint16_t AlControl::encode() const {
  return static_cast<std::uint16_t>((state_bits & reg::kAlStateMask) |
                                    (acknowledge ? reg::kAlErrorFlag : 0U) |
                                    (request_id ? reg::kAlDeviceIdentification : 0U));
}

AlControl AlControl::decode(std::uint16_t value) {
  return AlControl{static_cast<std::uint8_t>(value & reg::kAlStateMask), (value & reg::kAlErrorFlag) != 0,
                   (value & reg::kAlDeviceIdentification) != 0};
}

FmmuConfig FmmuConfig::bytes(std::uint32_t logical, std::uint16_t physical, std::uint16_t size,
                             std::uint8_t fmmu_type) {
  FmmuConfig f;
  f.logical_start = logical;
  f.length = size;
  f.logical_start_bit = 0;
  f.logical_stop_bit = 7;
  f.physical_start = physical;
  f.physical_start_bit = 0;
  f.type = fmmu_type;
  f.active = true;
  return f;
}

std::array<std::uint8_t, FmmuConfig::kSize> FmmuConfig::encode() const {
  std::array<std::uint8_t, kSize> out{};
  SpanWriter w(out);
  w.u32(logical_start);
  w.u16(length);
  w.u8(logical_start_bit);
  w.u8(logical_stop_bit);
  w.u16(physical_start);
  w.u8(physical_start_bit);
  w.u8(type);
  w.u8(active ? 1 : 0);
  return out;  // bytes 0x0D–0x0F reserved, zero
}

Result<FmmuConfig> FmmuConfig::decode(ByteSpan bytes) {
  if (bytes.size() < kSize) {
    return make_error(Errc::malformed, fmt::format("FMMU: needs {} bytes, got {}", kSize, bytes.size()));
  }
  ByteReader r(bytes);
  FmmuConfig f;
  f.logical_start = r.u32();
  f.length = r.u16();
  f.logical_start_bit = r.u8();
  f.logical_stop_bit = r.u8();
  f.physical_start = r.u16();
  f.physical_start_bit = r.u8();
  f.type = r.u8();
  f.active = (r.u8() & 0x01U) != 0;
  // Datasheet II §11: bit numbers are 3-bit fields; larger values are not a
  // configuration an ESC could hold.
  if (f.logical_start_bit > 7 || f.logical_stop_bit > 7 || f.physical_start_bit > 7) {
    return make_error(Errc::malformed,
                      fmt::format("FMMU: bit number out of range (start {}, stop {}, physical {})",
                                  f.logical_start_bit, f.logical_stop_bit, f.physical_start_bit));
  }
  return f;
}

SyncManagerMode SyncManagerConfig::mode() const {
  return (control & sm::kModeMask) == static_cast<std::uint8_t>(SyncManagerMode::mailbox)
             ? SyncManagerMode::mailbox
             : SyncManagerMode::buffered;
}

SyncManagerDirection SyncManagerConfig::direction() const {
  return (control & sm::kDirectionMask) == 0 ? SyncManagerDirection::read : SyncManagerDirection::write;
}

SyncManagerConfig SyncManagerConfig::make(std::uint16_t sm_start, std::uint16_t sm_length,
                                          SyncManagerMode sm_mode, SyncManagerDirection sm_direction,
                                          bool enable) {
  SyncManagerConfig c;
  c.start = sm_start;
  c.length = sm_length;
  c.control =
      static_cast<std::uint8_t>(static_cast<unsigned>(sm_mode) | (static_cast<unsigned>(sm_direction) << 2U));
  if (sm_mode == SyncManagerMode::mailbox) {
    c.control = static_cast<std::uint8_t>(c.control | sm::kPdiInterrupt);
  }
  c.activate = enable ? sm::kActivateEnable : std::uint8_t{0};
  return c;
}

std::array<std::uint8_t, SyncManagerConfig::kSize> SyncManagerConfig::encode() const {
  std::array<std::uint8_t, kSize> out{};
  SpanWriter w(out);
  w.u16(start);
  w.u16(length);
  w.u8(control);
  w.u8(status);
  w.u8(activate);
  w.u8(pdi_control);
  return out;
}

Result<SyncManagerConfig> SyncManagerConfig::decode(ByteSpan bytes) {
  if (bytes.size() < kSize) {
    return make_error(Errc::malformed,
                      fmt::format("SyncManager: needs {} bytes, got {}", kSize, bytes.size()));
  }
  ByteReader r(bytes);
  SyncManagerConfig c;
  c.start = r.u16();
  c.length = r.u16();
  c.control = r.u8();
  c.status = r.u8();
  c.activate = r.u8();
  c.pdi_control = r.u8();
  return c;
}

}  // namespace sf::ethercat
