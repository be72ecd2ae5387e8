// PDO mapping: which objects travel in the process data, and at which bit.
// From CoE (ETG.1000.6 §5.6.7.4, CiA 301): 0x1C12 lists the RxPDOs assigned
// to SM2, 0x1C13 the TxPDOs assigned to SM3; each PDO object (0x16xx/0x1Axx)
// lists its entries as u32 "index << 16 | subindex << 8 | bit length".
// Without CoE the SII RxPDO/TxPDO categories (ETG.2010 §2.8) say the same.
#include <fmt/format.h>

#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::master {
namespace {

constexpr std::uint16_t kRxPdoAssign = 0x1C12;
constexpr std::uint16_t kTxPdoAssign = 0x1C13;
// Objects 0x1C12/0x1C13 have at most 254 subindices; PDOs at most 254 entries.
constexpr std::uint8_t kMaxSubindex = 254;

void add_entry(Pdo& pdo, std::uint32_t& bit_offset, std::uint16_t index, std::uint8_t subindex,
               std::uint8_t bits) {
  pdo.entries.push_back(PdoEntry{index, subindex, bits, bit_offset});
  pdo.bit_length += bits;
  bit_offset += bits;
}

}  // namespace

Result<PdoMapping> Master::read_pdo_mapping_coe(std::size_t position) {
  PdoMapping mapping;
  mapping.source = PdoMapping::Source::coe;
  for (const auto assign : {kRxPdoAssign, kTxPdoAssign}) {
    const bool outputs = assign == kRxPdoAssign;
    auto& pdos = outputs ? mapping.outputs : mapping.inputs;
    std::uint32_t& bits = outputs ? mapping.output_bits : mapping.input_bits;
    auto count = sdo_read<std::uint8_t>(position, assign, 0);
    if (!count) {
      return count.error();
    }
    if (*count > kMaxSubindex) {
      return make_error(Errc::malformed,
                        fmt::format("slave {}: 0x{:04x} lists {} PDOs", position, assign, *count));
    }
    for (std::uint8_t i = 1; i <= *count; ++i) {
      auto pdo_index = sdo_read<std::uint16_t>(position, assign, i);
      if (!pdo_index) {
        return pdo_index.error();
      }
      Pdo pdo;
      pdo.index = *pdo_index;
      auto entries = sdo_read<std::uint8_t>(position, pdo.index, 0);
      if (!entries) {
        return entries.error();
      }
      if (*entries > kMaxSubindex) {
        return make_error(Errc::malformed, fmt::format("slave {}: PDO 0x{:04x} has {} entries", position,
                                                       pdo.index, *entries));
      }
      for (std::uint8_t j = 1; j <= *entries; ++j) {
        auto e = sdo_read<std::uint32_t>(position, pdo.index, j);
        if (!e) {
          return e.error();
        }
        add_entry(pdo, bits, static_cast<std::uint16_t>(*e >> 16U), static_cast<std::uint8_t>(*e >> 8U),
                  static_cast<std::uint8_t>(*e));
      }
      pdos.push_back(std::move(pdo));
    }
  }
  return mapping;
}

Result<PdoMapping> Master::read_pdo_mapping_sii(std::size_t position) const {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  const auto& sii = slaves_[position].sii;
  PdoMapping mapping;
  mapping.source = PdoMapping::Source::sii;
  // A PDO with SyncManager 0xFF is an alternative the slave offers, not
  // assigned by default (ETG.2010 Table 13).
  for (const auto* list : {&sii.rx_pdos, &sii.tx_pdos}) {
    const bool outputs = list == &sii.rx_pdos;
    auto& pdos = outputs ? mapping.outputs : mapping.inputs;
    std::uint32_t& bits = outputs ? mapping.output_bits : mapping.input_bits;
    for (const auto& sii_pdo : *list) {
      if (sii_pdo.sync_manager == 0xFF) {
        continue;
      }
      Pdo pdo;
      pdo.index = sii_pdo.index;
      for (const auto& e : sii_pdo.entries) {
        add_entry(pdo, bits, e.index, e.subindex, e.bit_length);
      }
      pdos.push_back(std::move(pdo));
    }
  }
  return mapping;
}

Result<PdoMapping> Master::read_pdo_mapping(std::size_t position) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  const auto& s = slaves_[position];
  const bool pdo_assign_via_coe =
      s.mailbox.coe() && (!s.sii.general || (s.sii.general->coe_details & sii::coe_details::kSdo) != 0);
  if (pdo_assign_via_coe) {
    auto coe = read_pdo_mapping_coe(position);
    if (coe) {
      return coe;
    }
    // A CoE slave without 0x1C12/0x1C13 (abort "object does not exist") still
    // describes its fixed mapping in the SII; any other failure is one.
    const ProtocolCode missing{kSdoAbortTable, static_cast<std::uint32_t>(SdoAbortCode::ObjectDoesNotExist)};
    if (coe.error().protocol_code != missing) {
      return coe.error();
    }
    log_->info("slave {}: no PDO assignment via CoE ({}), using SII", position, coe.error().message);
  }
  return read_pdo_mapping_sii(position);
}

}  // namespace sf::ethercat::master
