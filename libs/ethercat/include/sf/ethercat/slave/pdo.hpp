// PDO mapping and assignment (ETG.1000.6 §5.6.7.4, CiA 301 §7.5.2.35/36):
// mapping objects 0x1600–0x17FF (RxPDO, outputs) and 0x1A00–0x1BFF (TxPDO,
// inputs) list the mapped objects as UNSIGNED32 (index << 16 | subindex << 8
// | bit length); the SyncManager assignment objects 0x1C12 (outputs) and
// 0x1C13 (inputs) list the PDOs. A master may remap in PREOP: subindex 0 is
// set to 0, the entries are written, then subindex 0 to the new count.
//
// PdoMap compiles an assignment into a flat list of (object, bit offset) so
// that the cyclic copy between SyncManager buffer and objects does no lookups.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/ethercat/slave/object_dictionary.hpp"

namespace sf::ethercat::slave {

inline constexpr std::uint16_t kRxPdoMappingFirst = 0x1600;
inline constexpr std::uint16_t kRxPdoMappingLast = 0x17FF;
inline constexpr std::uint16_t kTxPdoMappingFirst = 0x1A00;
inline constexpr std::uint16_t kTxPdoMappingLast = 0x1BFF;
inline constexpr std::uint16_t kRxPdoAssignment = 0x1C12;
inline constexpr std::uint16_t kTxPdoAssignment = 0x1C13;

// One mapped object: what a mapping entry's UNSIGNED32 encodes. Index 0 (or a
// data type index 0x0001–0x0007 with subindex 0) is a gap of bit_length bits.
struct PdoEntryRef {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t bit_length = 0;

  [[nodiscard]] std::uint32_t encode() const {
    return (std::uint32_t{index} << 16U) | (std::uint32_t{subindex} << 8U) | bit_length;
  }
  static PdoEntryRef decode(std::uint32_t v) {
    return PdoEntryRef{static_cast<std::uint16_t>(v >> 16U), static_cast<std::uint8_t>(v >> 8U),
                       static_cast<std::uint8_t>(v)};
  }
  [[nodiscard]] bool is_gap() const { return index == 0 || (index <= 0x0007 && subindex == 0); }
};

// Adds a mapping object with `capacity` entries (the first entries.size()
// in use); `configurable`: writable in PREOP with the CiA 301 rules.
OdObject& add_pdo_mapping(ObjectDictionary& od, std::uint16_t index, std::string name,
                          std::span<const PdoEntryRef> entries, bool configurable, std::uint8_t capacity = 8);
// Adds 0x1C12 or 0x1C13 with the given PDOs assigned.
OdObject& add_pdo_assignment(ObjectDictionary& od, std::uint16_t index, std::span<const std::uint16_t> pdos,
                             bool configurable, std::uint8_t capacity = 16);

class PdoMap {
 public:
  // Compiles the assignment object (0x1C12 or 0x1C13). Returns 0 or the AL
  // status code for an invalid mapping (0x0025 outputs, 0x0024 inputs).
  std::uint16_t build(ObjectDictionary& od, std::uint16_t assignment_index);
  void clear() {
    items_.clear();
    bits_ = 0;
  }

  [[nodiscard]] std::size_t bit_size() const { return bits_; }
  [[nodiscard]] std::size_t byte_size() const { return (bits_ + 7U) / 8U; }
  [[nodiscard]] bool empty() const { return items_.empty(); }

  // SyncManager buffer → mapped objects (RxPDO) / mapped objects → buffer
  // (TxPDO). A buffer shorter than byte_size() is copied as far as it goes.
  void unpack(ByteSpan buffer) const;
  void pack(MutableByteSpan buffer) const;

 private:
  struct Item {
    OdEntry* entry = nullptr;
    std::uint32_t bit_offset = 0;
    std::uint16_t bits = 0;
  };
  std::vector<Item> items_;
  std::size_t bits_ = 0;
};

}  // namespace sf::ethercat::slave
