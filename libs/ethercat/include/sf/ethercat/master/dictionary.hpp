// A slave's object dictionary as the SDO Information service describes it
// (ETG.1000.6 §5.6.3): what `ecat sdo list` prints, like SOEM's
// `slaveinfo -sdo` or the IgH master's `ethercat sdos`.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/sdo_info.hpp"

namespace sf::ethercat::master {

struct DictionaryEntry {
  EntryDescription description;
  // Read when values were asked for and the entry is readable; an abort of
  // the read is kept as the answer.
  std::optional<SdoAnswer<Bytes>> value;
};

struct DictionaryObject {
  ObjectDescription description;
  std::vector<DictionaryEntry> entries;  // the subindices that exist, in order
};

// Every object of the slave's "all objects" list with its entries; with
// `values`, each readable entry's current value too. Fails on the first
// transfer that gets no usable answer, or when the slave refuses the list.
Result<std::vector<DictionaryObject>> read_dictionary(Master& master, std::size_t position, bool values);

}  // namespace sf::ethercat::master
