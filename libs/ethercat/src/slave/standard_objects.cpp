#include "sf/ethercat/slave/standard_objects.hpp"

#include "sf/ethercat/slave/pdo.hpp"

namespace sf::ethercat::slave {

void add_identity_objects(ObjectDictionary& od, const DeviceIdentity& identity) {
  od.add_var(0x1000, "Device type", DataType::Unsigned32, access::kRO, identity.device_type);
  od.add_var(0x1001, "Error register", DataType::Unsigned8, access::kRO | access::kTxPdo, 0);
  od.add_string(0x1008, "Device name", identity.name);
  od.add_string(0x1009, "Hardware version", identity.hardware_version);
  od.add_string(0x100A, "Software version", identity.software_version);
  OdObject& id = od.add_compound(0x1018, "Identity", ObjectCode::Record);
  od.add_entry(id, 1, "Vendor ID", DataType::Unsigned32, access::kRO, identity.vendor_id);
  od.add_entry(id, 2, "Product code", DataType::Unsigned32, access::kRO, identity.product_code);
  od.add_entry(id, 3, "Revision", DataType::Unsigned32, access::kRO, identity.revision);
  od.add_entry(id, 4, "Serial number", DataType::Unsigned32, access::kRO, identity.serial);
}

void add_sync_manager_objects(ObjectDictionary& od, std::span<const SiiSyncManager> sync_managers) {
  OdObject& types = od.add_compound(0x1C00, "Sync manager type", ObjectCode::Array);
  bool outputs = false;
  bool inputs = false;
  for (std::size_t n = 0; n < sync_managers.size(); ++n) {
    od.add_entry(types, static_cast<std::uint8_t>(n + 1), "SubIndex " + std::to_string(n + 1),
                 DataType::Unsigned8, access::kRO, static_cast<std::uint8_t>(sync_managers[n].type));
    outputs |= sync_managers[n].type == SiiSyncManagerType::outputs;
    inputs |= sync_managers[n].type == SiiSyncManagerType::inputs;
  }
  // ETG.1020 §21: SyncManager parameters; synchronization type 0 free run,
  // 1 synchronous with SM event, 2 DC SYNC0.
  auto add_parameters = [&od](std::uint16_t index, const char* name) {
    OdObject& p = od.add_compound(index, name, ObjectCode::Record);
    od.add_entry(p, 1, "Synchronization type", DataType::Unsigned16, access::kRW, 1);
    od.add_entry(p, 2, "Cycle time", DataType::Unsigned32, access::kRW, 1'000'000);
    od.add_entry(p, 4, "Synchronization types supported", DataType::Unsigned16, access::kRO, 0x0007);
    od.add_entry(p, 5, "Minimum cycle time", DataType::Unsigned32, access::kRO, 125'000);
    od.add_entry(p, 6, "Calc and copy time", DataType::Unsigned32, access::kRO, 10'000);
    od.add_entry(p, 9, "Delay time", DataType::Unsigned32, access::kRO, 0);
    od.add_entry(p, 12, "Cycle time too small", DataType::Unsigned16, access::kRO, 0);
    od.add_entry(p, 32, "Sync error", DataType::Boolean, access::kRO, 0);
  };
  if (outputs) {
    add_parameters(0x1C32, "SM output parameter");
  }
  if (inputs) {
    add_parameters(0x1C33, "SM input parameter");
  }
}

std::vector<SiiPdo> sii_pdos(const ObjectDictionary& od, std::uint16_t assignment, std::uint8_t sync_manager,
                             bool fixed) {
  std::vector<SiiPdo> out;
  const OdObject* assign = od.find(assignment);
  if (assign == nullptr) {
    return out;
  }
  for (std::uint8_t a = 1; a <= assign->count(); ++a) {
    const OdEntry* ref = assign->entry(a);
    const OdObject* pdo = ref == nullptr ? nullptr : od.find(ref->get<std::uint16_t>());
    if (pdo == nullptr) {
      continue;
    }
    SiiPdo p;
    p.index = pdo->index();
    p.sync_manager = sync_manager;
    p.name = pdo->name();
    p.flags = fixed ? 0x0010 : 0x0000;  // ETG.2010 PDO flags: bit 4 fixed content
    for (std::uint8_t s = 1; s <= pdo->count(); ++s) {
      const OdEntry* m = pdo->entry(s);
      if (m == nullptr) {
        continue;
      }
      const PdoEntryRef e = PdoEntryRef::decode(m->get<std::uint32_t>());
      const OdEntry* target = e.is_gap() ? nullptr : od.find(e.index, e.subindex);
      const OdObject* target_obj = e.is_gap() ? nullptr : od.find(e.index);
      SiiPdoEntry entry;
      entry.index = e.index;
      entry.subindex = e.subindex;
      entry.bit_length = e.bit_length;
      if (target != nullptr) {
        entry.name = target_obj->code() == ObjectCode::Var ? target_obj->name() : target->name;
        entry.data_type = static_cast<std::uint8_t>(target->type);
      }
      p.entries.push_back(std::move(entry));
    }
    out.push_back(std::move(p));
  }
  return out;
}

Status fit_eeprom_size(SiiInfo& info) {
  info.size = 1;  // 2 KiBit
  for (;;) {
    auto image = encode_sii(info);
    if (!image) {
      return image.error();
    }
    const std::size_t bytes = (std::size_t{info.size} + 1U) * 128U;
    if (image->size() <= bytes) {
      return {};
    }
    if (info.size >= 0x3FF) {
      return make_error(Errc::limit_exceeded, "SII image does not fit the largest EEPROM");
    }
    info.size = static_cast<std::uint16_t>(2U * (info.size + 1U) - 1U);
  }
}

}  // namespace sf::ethercat::slave
