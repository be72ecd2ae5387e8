// The plant's control port on arbitrary request lines: every line gets one
// JSON answer ({"ok": false, "error": ...} for nonsense) and the plant goes on.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

#include "sf/core/clock.hpp"
#include "sf/plant/control.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static sf::ManualClock clock;
  static auto plant = std::make_unique<sf::plant::Plant>(*sf::plant::default_layout(), clock);
  const std::string_view line(reinterpret_cast<const char*>(data), size);  // NOLINT
  const std::string answer = sf::plant::handle_control_request(*plant, line);
  if (answer.empty() || answer.front() != '{') {
    __builtin_trap();
  }
  auto lock = plant->lock();
  plant->advance(std::chrono::milliseconds{1});
  return 0;
}
