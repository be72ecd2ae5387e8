// Engineering units of analog values (OPC 10000-8 §5.6.3 EUInformation): the UNECE Recommendation
// 20 units, named by their common code ("CEL" degree Celsius, "C81" radian, "MTR" metre).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "sf/opcua/encoding.hpp"

namespace sf::opcua {

inline constexpr std::string_view kUneceUnitsNamespace = "http://www.opcfoundation.org/UA/units/un/cefact";

// §5.6.3: the UnitId of a common code: its (up to three) characters, big-endian, one byte each.
constexpr std::int32_t unece_unit_id(std::string_view common_code) {
  std::int32_t id = 0;
  for (const char c : common_code.substr(0, 3)) {
    id = (id << 8) | static_cast<std::uint8_t>(c);
  }
  return id;
}

// The EUInformation of a UNECE unit; `symbol` becomes its DisplayName ("°C"), `name` its
// Description ("degree Celsius").
inline EUInformation unece_unit(std::string_view common_code, std::string_view symbol,
                                std::string_view name) {
  EUInformation eu;
  eu.namespace_uri = String(kUneceUnitsNamespace);
  eu.unit_id = unece_unit_id(common_code);
  eu.display_name = LocalizedText("en", String(symbol));
  eu.description = LocalizedText("en", String(name));
  return eu;
}

// The units the shop floor's controllers publish, by common code (UNECE Rec 20 Annex I):
// nullopt for a code not in this list.
inline std::optional<EUInformation> unece_unit(std::string_view common_code) {
  struct Known {
    std::string_view code, symbol, name;
  };
  static constexpr Known kKnown[] = {
      {"C81", "rad", "radian"},
      {"DD", "°", "degree [unit of angle]"},
      {"MTR", "m", "metre"},
      {"MMT", "mm", "millimetre"},
      {"CEL", "°C", "degree Celsius"},
      {"KEL", "K", "kelvin"},
      {"MTS", "m/s", "metre per second"},
      {"GRM", "g", "gram"},
  };
  for (const Known& k : kKnown) {
    if (k.code == common_code) {
      return unece_unit(k.code, k.symbol, k.name);
    }
  }
  return std::nullopt;
}

}  // namespace sf::opcua
