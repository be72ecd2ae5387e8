// Objects every emulated CoE device has (CiA 301 §7.5.2, ETG.1000.6 §5.6.7)
// and the SII pieces derived from them, so the EEPROM and the object
// dictionary of a device can never disagree.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/ethercat/sii.hpp"
#include "sf/ethercat/slave/object_dictionary.hpp"

namespace sf::ethercat::slave {

// Our vendor ID ("SF"); product codes below. Not an ETG-assigned number: an
// emulator must not pretend to be someone else's hardware.
inline constexpr std::uint32_t kVendorId = 0x00005346;

struct DeviceIdentity {
  std::uint32_t device_type = 0;  // 0x1000: profile number (low word) + additional information
  std::uint32_t vendor_id = kVendorId;
  std::uint32_t product_code = 0;
  std::uint32_t revision = 0x00010000;
  std::uint32_t serial = 0;
  std::string name;
  std::string hardware_version = "1.0";
  std::string software_version = "1.0";
};

// 0x1000 device type, 0x1001 error register, 0x1008 name, 0x1009/0x100A
// versions, 0x1018 identity.
void add_identity_objects(ObjectDictionary& od, const DeviceIdentity& identity);
// 0x1C00 SyncManager communication types and, when there is process data,
// 0x1C32/0x1C33 SyncManager parameters (synchronization type, cycle time).
void add_sync_manager_objects(ObjectDictionary& od, std::span<const SiiSyncManager> sync_managers);
// SII TxPDO/RxPDO category entries for the PDOs assigned in 0x1C13/0x1C12.
std::vector<SiiPdo> sii_pdos(const ObjectDictionary& od, std::uint16_t assignment, std::uint8_t sync_manager,
                             bool fixed);
// Sets SiiInfo::size to the smallest EEPROM (2^n KiBit) the image fits in.
Status fit_eeprom_size(SiiInfo& info);

}  // namespace sf::ethercat::slave
