// The inspection text and the order step the cloud reads from the order service's OPC UA server
// (sf/line/inspection.hpp) on arbitrary bytes: a clear error or a record, and a record
// reads back the same from its own text.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sf/line/inspection.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);  // NOLINT
  if (auto step = sf::line::parse_order_step(text); step) {
    auto again = sf::line::parse_order_step(sf::line::format_order_step(*step));
    if (!again || *again != *step) {
      __builtin_trap();
    }
  } else if (step.error().message.empty()) {
    __builtin_trap();
  }
  auto record = sf::line::parse_inspection(text);
  if (!record) {
    if (record.error().message.empty()) {
      __builtin_trap();
    }
    return 0;
  }
  auto again = sf::line::parse_inspection(sf::line::format_inspection(*record));
  // Numbers go through the text with fixed decimals: compare what the text keeps exactly.
  if (!again || again->order != record->order || again->box != record->box ||
      again->ordered != record->ordered || again->counted != record->counted ||
      again->box_type != record->box_type) {
    __builtin_trap();
  }
  return 0;
}
