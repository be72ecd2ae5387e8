#include "sf/ethercat/slave/pdo.hpp"

#include <cstring>

#include "bits.hpp"
#include "sf/ethercat/al_status_codes.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::slave {

namespace {

using detail::copy_bits;

constexpr std::size_t kMaxPdoBits = 8U * 1024U;  // largest PDO we accept (1 KiB)

bool is_rx_mapping(std::uint16_t index) {
  return index >= kRxPdoMappingFirst && index <= kRxPdoMappingLast;
}
bool is_tx_mapping(std::uint16_t index) {
  return index >= kTxPdoMappingFirst && index <= kTxPdoMappingLast;
}

// CiA 301 §7.5.2.36: entries may only change while subindex 0 is 0.
AbortCode guard_entries(const OdObject& obj, std::uint8_t subindex) {
  if (subindex != 0 && obj.count() != 0) {
    return abort_code(SdoAbortCode::SubindexCannotBeWritten);
  }
  return 0;
}

// Checks one mapping entry against the dictionary; adds its bits to *bits.
AbortCode check_mapped(const ObjectDictionary& od, PdoEntryRef ref, bool rx, std::size_t* bits) {
  *bits += ref.bit_length;
  if (ref.is_gap()) {
    return 0;
  }
  const OdEntry* e = od.find(ref.index, ref.subindex);
  const std::uint16_t needed = rx ? access::kRxPdo : access::kTxPdo;
  if (e == nullptr || (e->access & needed) == 0 || e->bit_length != ref.bit_length) {
    return abort_code(SdoAbortCode::CannotBeMapped);
  }
  return 0;
}

AbortCode validate_mapping(const ObjectDictionary& od, const OdObject& obj, std::uint8_t subindex,
                           ByteSpan data) {
  if (AbortCode c = guard_entries(obj, subindex); c != 0) {
    return c;
  }
  const bool rx = is_rx_mapping(obj.index());
  if (subindex != 0) {
    std::size_t bits = 0;
    return check_mapped(od, PdoEntryRef::decode(load_le<std::uint32_t>(data.data())), rx, &bits);
  }
  const std::uint8_t n = data[0];
  if (n > obj.max_subindex()) {
    return abort_code(SdoAbortCode::ValueTooHigh);
  }
  std::size_t bits = 0;
  for (std::uint8_t s = 1; s <= n; ++s) {
    const OdEntry* e = obj.entry(s);
    if (e == nullptr) {
      return abort_code(SdoAbortCode::CannotBeMapped);
    }
    if (AbortCode c = check_mapped(od, PdoEntryRef::decode(e->get<std::uint32_t>()), rx, &bits); c != 0) {
      return c;
    }
  }
  return bits > kMaxPdoBits ? abort_code(SdoAbortCode::PdoLengthExceeded) : 0;
}

AbortCode validate_assignment(const ObjectDictionary& od, const OdObject& obj, std::uint8_t subindex,
                              ByteSpan data) {
  if (AbortCode c = guard_entries(obj, subindex); c != 0) {
    return c;
  }
  const bool rx = obj.index() == kRxPdoAssignment;
  auto valid_pdo = [&](std::uint16_t pdo) {
    return (rx ? is_rx_mapping(pdo) : is_tx_mapping(pdo)) && od.find(pdo) != nullptr;
  };
  if (subindex != 0) {
    return valid_pdo(load_le<std::uint16_t>(data.data())) ? 0 : abort_code(SdoAbortCode::ValueRangeExceeded);
  }
  const std::uint8_t n = data[0];
  if (n > obj.max_subindex()) {
    return abort_code(SdoAbortCode::ValueTooHigh);
  }
  for (std::uint8_t s = 1; s <= n; ++s) {
    const OdEntry* e = obj.entry(s);
    if (e == nullptr || !valid_pdo(e->get<std::uint16_t>())) {
      return abort_code(SdoAbortCode::ValueRangeExceeded);
    }
  }
  return 0;
}

}  // namespace

OdObject& add_pdo_mapping(ObjectDictionary& od, std::uint16_t index, std::string name,
                          std::span<const PdoEntryRef> entries, bool configurable, std::uint8_t capacity) {
  const std::uint16_t acc = configurable ? access::kRWPreOp : access::kRO;
  OdObject& obj = od.add_compound(index, std::move(name), ObjectCode::Record, acc);
  const std::size_t n = std::max<std::size_t>(capacity, entries.size());
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t v = i < entries.size() ? entries[i].encode() : 0;
    od.add_entry(obj, static_cast<std::uint8_t>(i + 1), "SubIndex " + std::to_string(i + 1),
                 DataType::Unsigned32, acc, v);
  }
  obj.entry(0)->set<std::uint8_t>(static_cast<std::uint8_t>(entries.size()));
  obj.set_validator(
      [&od](const OdObject& o, std::uint8_t s, ByteSpan d) { return validate_mapping(od, o, s, d); });
  return obj;
}

OdObject& add_pdo_assignment(ObjectDictionary& od, std::uint16_t index, std::span<const std::uint16_t> pdos,
                             bool configurable, std::uint8_t capacity) {
  const std::uint16_t acc = configurable ? access::kRWPreOp : access::kRO;
  OdObject& obj = od.add_compound(index, index == kRxPdoAssignment ? "RxPDO assign" : "TxPDO assign",
                                  ObjectCode::Array, acc);
  const std::size_t n = std::max<std::size_t>(capacity, pdos.size());
  for (std::size_t i = 0; i < n; ++i) {
    od.add_entry(obj, static_cast<std::uint8_t>(i + 1), "SubIndex " + std::to_string(i + 1),
                 DataType::Unsigned16, acc, i < pdos.size() ? pdos[i] : 0);
  }
  obj.entry(0)->set<std::uint8_t>(static_cast<std::uint8_t>(pdos.size()));
  obj.set_validator(
      [&od](const OdObject& o, std::uint8_t s, ByteSpan d) { return validate_assignment(od, o, s, d); });
  return obj;
}

std::uint16_t PdoMap::build(ObjectDictionary& od, std::uint16_t assignment_index) {
  clear();
  const bool rx = assignment_index == kRxPdoAssignment;
  const auto invalid =
      static_cast<std::uint16_t>(rx ? AlStatusCode::InvalidOutputMapping : AlStatusCode::InvalidInputMapping);
  const OdObject* assignment = od.find(assignment_index);
  if (assignment == nullptr) {
    return 0;  // nothing assigned: no process data in this direction
  }
  std::size_t bits = 0;
  for (std::uint8_t a = 1; a <= assignment->count(); ++a) {
    const OdEntry* pdo_ref = assignment->entry(a);
    const OdObject* pdo = pdo_ref == nullptr ? nullptr : od.find(pdo_ref->get<std::uint16_t>());
    if (pdo == nullptr) {
      return invalid;
    }
    for (std::uint8_t s = 1; s <= pdo->count(); ++s) {
      const OdEntry* m = pdo->entry(s);
      if (m == nullptr) {
        return invalid;
      }
      const PdoEntryRef ref = PdoEntryRef::decode(m->get<std::uint32_t>());
      std::size_t unused = 0;
      if (check_mapped(od, ref, rx, &unused) != 0) {
        clear();
        return invalid;
      }
      if (!ref.is_gap()) {
        items_.push_back(
            Item{od.find(ref.index, ref.subindex), static_cast<std::uint32_t>(bits), ref.bit_length});
      }
      bits += ref.bit_length;
    }
  }
  bits_ = bits;
  return 0;
}

void PdoMap::unpack(ByteSpan buffer) const {
  for (const Item& item : items_) {
    if (item.bit_offset + item.bits <= 8U * buffer.size()) {
      copy_bits(buffer.data(), item.bit_offset, item.entry->value.data(), 0, item.bits);
    }
  }
}

void PdoMap::pack(MutableByteSpan buffer) const {
  for (const Item& item : items_) {
    if (item.bit_offset + item.bits <= 8U * buffer.size()) {
      copy_bits(item.entry->value.data(), 0, buffer.data(), item.bit_offset, item.bits);
    }
  }
}

}  // namespace sf::ethercat::slave
