// SDO Information server (ETG.1000.6 §5.6.3) over an ObjectDictionary: the
// OD lists, object and entry descriptions a CoE client asks for to list a
// slave's dictionary. Refusals are SDO Info Error requests with an SDO abort
// code, as a client expects them (an unknown opcode: 0x05040001).
#pragma once

#include <cstddef>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/ethercat/sdo_info.hpp"
#include "sf/ethercat/slave/object_dictionary.hpp"

namespace sf::ethercat::slave::detail {

class SdoInfoServer {
 public:
  explicit SdoInfoServer(const ObjectDictionary& od) : od_(&od) {}

  // The answer to one request (the CoE body after the CoE header; at least
  // the SDO Info header) as CoE bodies, one per fragment, for a read mailbox
  // of `mailbox_size` bytes.
  [[nodiscard]] std::vector<Bytes> handle(ByteSpan body, std::size_t mailbox_size) const;

 private:
  [[nodiscard]] SdoInfoMessage answer(const SdoInfoMessage& request) const;
  [[nodiscard]] SdoInfoMessage od_list(OdListType type) const;
  [[nodiscard]] SdoInfoMessage object_description(std::uint16_t index) const;
  [[nodiscard]] SdoInfoMessage entry_description(const EntryDescriptionRequest& r) const;

  const ObjectDictionary* od_;
};

}  // namespace sf::ethercat::slave::detail
