// Digital IO without a mailbox: its fixed PDOs are described only by the SII
// TxPDO/RxPDO categories (ETG.2010 §2.7), as on simple terminals.
#include "sf/core/log.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/pdo.hpp"
#include "sf/ethercat/slave/standard_objects.hpp"

namespace sf::ethercat::slave {

namespace {
constexpr std::uint32_t kDeviceTypeDigitalIo = 0x00001389;  // modular device profile (ETG.5001)
constexpr std::uint16_t kOutputsSm = 0x1000;
constexpr std::uint16_t kInputsSm = 0x1080;
}  // namespace

DigitalIo::DigitalIo(const DeviceOptions& options) {
  // The dictionary is internal (no CoE): it only carries the fixed mapping.
  add_identity_objects(od_, DeviceIdentity{kDeviceTypeDigitalIo, kVendorId, kDigitalIoProductCode, 0x00010000,
                                           options.serial, "Digital IO (8 DI, 8 DO)", "1.0", "1.0"});
  inputs_ = &od_.add_var(0x6000, "Digital inputs", DataType::Unsigned8, access::kRO | access::kTxPdo);
  outputs_ = &od_.add_var(0x7000, "Digital outputs", DataType::Unsigned8, access::kRW | access::kRxPdo);
  const PdoEntryRef rx_entries[] = {{0x7000, 0, 8}};
  const PdoEntryRef tx_entries[] = {{0x6000, 0, 8}};
  add_pdo_mapping(od_, kRxPdoMappingFirst, "Digital outputs", rx_entries, false, 1);
  add_pdo_mapping(od_, kTxPdoMappingFirst, "Digital inputs", tx_entries, false, 1);
  const std::uint16_t rx[] = {kRxPdoMappingFirst};
  const std::uint16_t tx[] = {kTxPdoMappingFirst};
  add_pdo_assignment(od_, kRxPdoAssignment, rx, false, 1);
  add_pdo_assignment(od_, kTxPdoAssignment, tx, false, 1);

  sii_.pdi_control = 0x0004;  // digital IO PDI
  sii_.station_alias = options.station_alias;
  sii_.identity = SiiIdentity{kVendorId, kDigitalIoProductCode, 0x00010000, options.serial};
  SiiGeneral general;
  general.group = "smartfactory";
  general.order = std::string(kDigitalIoKind);
  general.name = "Digital IO (8 DI, 8 DO)";
  general.physical_port = 0x0011;
  sii_.general = general;
  sii_.fmmus = {SiiFmmuUsage::outputs, SiiFmmuUsage::inputs};
  // One-byte SyncManagers buffer nothing (datasheet II Table 90); SM0 still
  // triggers the process-data watchdog (control 0x44).
  sii_.sync_managers = {
      SiiSyncManager{kOutputsSm, 1, 0x44, 0, 0x01, SiiSyncManagerType::outputs},
      SiiSyncManager{kInputsSm, 1, 0x00, 0, 0x01, SiiSyncManagerType::inputs},
  };
  sii_.rx_pdos = sii_pdos(od_, kRxPdoAssignment, 0, true);
  sii_.tx_pdos = sii_pdos(od_, kTxPdoAssignment, 1, true);
  if (auto fitted = fit_eeprom_size(sii_); !fitted) {
    log::get("ethercat")->error("digital-io: {}", fitted.error().describe());
  }
}

void DigitalIo::apply_safe_outputs() {
  outputs_->set<std::uint8_t>(0);
}

void DigitalIo::power_on() {
  outputs_->set<std::uint8_t>(0);
}

}  // namespace sf::ethercat::slave
