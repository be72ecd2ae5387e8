#include "sf/ethercat/master/dictionary.hpp"

#include <fmt/format.h>

#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::master {
namespace {

// Read rights in any state (ETG.1000.6 Table 49 bits 0–2).
constexpr std::uint16_t kAnyRead = 0x0007;

Result<DictionaryObject> read_object(Master& master, std::size_t position, std::uint16_t index, bool values) {
  auto object = master.sdo_info_object(position, index);
  if (!object) {
    return object.error();
  }
  if (const auto* abort = std::get_if<SdoAbort>(&*object)) {
    return sdo_abort_error(*abort, fmt::format("slave {}: object description", position));
  }
  DictionaryObject out{std::get<ObjectDescription>(std::move(*object)), {}};
  for (unsigned sub = 0; sub <= out.description.max_subindex; ++sub) {
    auto entry = master.sdo_info_entry(position, index, static_cast<std::uint8_t>(sub));
    if (!entry) {
      return entry.error();
    }
    if (const auto* abort = std::get_if<SdoAbort>(&*entry)) {
      if (abort->code == static_cast<std::uint32_t>(SdoAbortCode::SubindexDoesNotExist)) {
        continue;  // gaps in an ARRAY/RECORD
      }
      return sdo_abort_error(*abort, fmt::format("slave {}: entry description", position));
    }
    DictionaryEntry e{std::get<EntryDescription>(std::move(*entry)), std::nullopt};
    if (values && (e.description.object_access & kAnyRead) != 0) {
      auto value = master.sdo_upload_answer(position, index, static_cast<std::uint8_t>(sub));
      if (!value) {
        return value.error();
      }
      e.value = std::move(*value);
    }
    out.entries.push_back(std::move(e));
  }
  return out;
}

}  // namespace

Result<std::vector<DictionaryObject>> read_dictionary(Master& master, std::size_t position, bool values) {
  auto list = master.sdo_info_od_list(position, OdListType::All);
  if (!list) {
    return list.error();
  }
  if (const auto* abort = std::get_if<SdoAbort>(&*list)) {
    return sdo_abort_error(*abort, fmt::format("slave {}: OD list", position));
  }
  std::vector<DictionaryObject> out;
  for (const auto index : std::get<std::vector<std::uint16_t>>(*list)) {
    auto object = read_object(master, position, index, values);
    if (!object) {
      return object.error();
    }
    out.push_back(std::move(*object));
  }
  return out;
}

}  // namespace sf::ethercat::master
