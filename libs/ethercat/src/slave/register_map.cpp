#include "register_map.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "sf/ethercat/registers.hpp"

namespace sf::ethercat::slave::detail {

namespace {

struct Builder {
  RegisterMap& map;

  void set(std::uint32_t from, std::uint32_t to_inclusive, std::uint8_t mask,
           RegGroup group = RegGroup::none) {
    for (std::uint32_t a = from; a <= to_inclusive; ++a) {
      map.write_mask[a] = mask;
      map.group[a] = group;
    }
  }
};

// ECAT write access per register, ET1100 datasheet II (tables of sections
// 3.x, column "ECAT"): r/w bits get a 1 in the mask, r/- bits a 0.
void build(RegisterMap& m, unsigned fmmus, unsigned sync_managers) {
  Builder b{m};
  b.set(reg::kStationAddress, reg::kStationAddress + 1U, 0xFF);
  // 0x0012 station alias: r/- for ECAT, loaded from SII word 4.
  b.set(reg::kRegisterWriteEnable, reg::kRegisterWriteEnable, 0x01, RegGroup::register_write_enable);
  b.set(reg::kRegisterWriteProtection, reg::kRegisterWriteProtection, 0x01);
  b.set(reg::kEscWriteEnable, reg::kEscWriteEnable, 0x01, RegGroup::esc_write_enable);
  b.set(reg::kEscWriteProtection, reg::kEscWriteProtection, 0x01);
  b.set(reg::kEscResetEcat, reg::kEscResetEcat, 0x00, RegGroup::esc_reset);
  // DL control: forwarding rule, loop control per port, RX FIFO, alias enable.
  b.set(reg::kDlControl, reg::kDlControl, 0x03, RegGroup::dl_control);
  b.set(reg::kDlControl + 1U, reg::kDlControl + 1U, 0xFF, RegGroup::dl_control);
  b.set(reg::kDlControl + 2U, reg::kDlControl + 2U, 0x4F, RegGroup::dl_control);
  b.set(reg::kDlControl + 3U, reg::kDlControl + 3U, 0x01, RegGroup::dl_control);
  b.set(reg::kPhysicalRwOffset, reg::kPhysicalRwOffset + 1U, 0xFF);
  b.set(reg::kAlControl, reg::kAlControl, 0x3F, RegGroup::al_control);
  b.set(reg::kAlControl + 1U, reg::kAlControl + 1U, 0xFF, RegGroup::al_control);
  b.set(reg::kAlStatus, reg::kAlStatus + 1U, 0x00, RegGroup::al_status);
  b.set(reg::kRunLedOverride, reg::kErrLedOverride, 0xFF);
  b.set(reg::kEcatEventMask, reg::kEcatEventMask + 1U, 0xFF);
  b.set(reg::kRxErrorCounter, reg::kLostLinkCounter + 3U, 0x00, RegGroup::error_counters);
  b.set(reg::kWatchdogDivider, reg::kWatchdogDivider + 1U, 0xFF, RegGroup::watchdog_config);
  b.set(reg::kWatchdogTimePdi, reg::kWatchdogTimePdi + 1U, 0xFF);
  b.set(reg::kWatchdogTimeProcessData, reg::kWatchdogTimeProcessData + 1U, 0xFF, RegGroup::watchdog_config);
  b.set(reg::kWatchdogCounterProcessData, reg::kWatchdogCounterPdi, 0x00, RegGroup::watchdog_counters);
  // SII interface (datasheet II §3.45): configuration, control/status
  // (write enable bit 0, command bits 10:8), address and data.
  b.set(reg::kSiiConfiguration, reg::kSiiConfiguration, 0x03);
  b.set(reg::kSiiControlStatus, reg::kSiiControlStatus, 0x01, RegGroup::sii_control);
  b.set(reg::kSiiControlStatus + 1U, reg::kSiiControlStatus + 1U, 0x07, RegGroup::sii_control);
  b.set(reg::kSiiAddress, reg::kSiiData + 7U, 0xFF, RegGroup::sii_registers);
  b.set(reg::kMiiControlStatus, reg::kMiiControlStatus, 0x01);
  b.set(reg::kMiiControlStatus + 1U, reg::kMiiControlStatus + 1U, 0x03);
  b.set(reg::kPhyAddress, reg::kPhyData + 1U, 0xFF);
  for (unsigned n = 0; n < fmmus && n < reg::kMaxFmmus; ++n) {
    const std::uint32_t base = reg::fmmu(n);
    b.set(base + 0x0U, base + 0x5U, 0xFF, RegGroup::fmmu);
    b.set(base + 0x6U, base + 0x7U, 0x07, RegGroup::fmmu);
    b.set(base + 0x8U, base + 0x9U, 0xFF, RegGroup::fmmu);
    b.set(base + 0xAU, base + 0xAU, 0x07, RegGroup::fmmu);
    b.set(base + 0xBU, base + 0xBU, 0x03, RegGroup::fmmu);
    b.set(base + 0xCU, base + 0xCU, 0x01, RegGroup::fmmu);
  }
  for (unsigned n = 0; n < sync_managers && n < reg::kMaxSyncManagers; ++n) {
    const std::uint32_t base = reg::sync_manager(n);
    b.set(base + reg::kSmStart, base + reg::kSmLength + 1U, 0xFF, RegGroup::sm_config);
    b.set(base + reg::kSmControl, base + reg::kSmControl, 0x7F, RegGroup::sm_config);
    b.set(base + reg::kSmStatus, base + reg::kSmStatus, 0x00, RegGroup::sm_status);
    b.set(base + reg::kSmActivate, base + reg::kSmActivate, 0xC3, RegGroup::sm_activate);
  }
  b.set(reg::kDcReceiveTimePort0, reg::kDcReceiveTimePort0 + 3U, 0x00, RegGroup::dc_receive_time);
  b.set(reg::kDcSystemTime, reg::kDcSystemTime + 7U, 0x00, RegGroup::dc_system_time);
  b.set(reg::kDcSystemTimeOffset, reg::kDcSystemTimeDelay + 3U, 0xFF);
  b.set(reg::kDcSpeedCounterStart, reg::kDcSpeedCounterStart, 0xFF, RegGroup::dc_speed_counter_start);
  b.set(reg::kDcSpeedCounterStart + 1U, reg::kDcSpeedCounterStart + 1U, 0x7F,
        RegGroup::dc_speed_counter_start);
  b.set(reg::kDcSystemTimeDiffFilterDepth, reg::kDcSpeedCounterFilterDepth, 0x0F);
  b.set(reg::kDcReceiveTimeLatchMode, reg::kDcReceiveTimeLatchMode, 0x01);
  b.set(reg::kDcCyclicUnitControl, reg::kDcCyclicUnitControl, 0x31, RegGroup::dc_cyclic);
  b.set(reg::kDcActivation, reg::kDcActivation, 0xFF, RegGroup::dc_cyclic);
  b.set(reg::kDcSync0Status, reg::kDcSync1Status, 0x00, RegGroup::dc_sync_status);
  b.set(reg::kDcStartTimeCyclic, reg::kDcStartTimeCyclic + 7U, 0xFF, RegGroup::dc_cyclic);
  b.set(reg::kDcSync0CycleTime, reg::kDcSync1CycleTime + 3U, 0xFF, RegGroup::dc_cyclic);
  b.set(reg::kDcLatch0Control, reg::kDcLatch1Control, 0x03);
  b.set(reg::kDigitalOutputData, reg::kDigitalOutputData + 3U, 0xFF);
  b.set(0x0F10, 0x0F17, 0xFF);  // general purpose outputs
  b.set(kUserRam, kRegisterAreaSize - 1U, 0xFF);
}

}  // namespace

const RegisterMap& register_map(unsigned fmmus, unsigned sync_managers) {
  static std::mutex mutex;
  static std::map<std::pair<unsigned, unsigned>, std::unique_ptr<RegisterMap>> cache;
  std::lock_guard lock(mutex);
  auto& slot = cache[{fmmus, sync_managers}];
  if (!slot) {
    slot = std::make_unique<RegisterMap>();
    build(*slot, fmmus, sync_managers);
  }
  return *slot;
}

}  // namespace sf::ethercat::slave::detail
