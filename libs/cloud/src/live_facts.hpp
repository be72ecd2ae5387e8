// Which OPC UA variables of the shop floor become which live facts of the ontology, and in what
// unit (knowledge_loop.hpp lists the mapping). Private to the knowledge loop.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"

namespace sf::cloud::detail {

// A value of the ontology measured by a machine: (p:<individual> sf:<property> value), value in
// the unit the ontology states for the property.
struct LiveQuantity {
  std::string individual;     // local name in the line's namespace: "ScaraRobot1Axis1"
  std::string_view property;  // "position", "temperature"
  double value = 0.0;
};

// The machine <M> of "/Objects/Machines/<M>/<leaf>", or nothing.
std::optional<std::string_view> machine_of(std::string_view path, std::string_view leaf);

// The quantity a variable's value is, when its path names one (nullopt: not a quantity); an
// error when it does but the value cannot be taken: not a number, or a unit (the variable's
// EngineeringUnits display name, OPC 10000-8 §5.6.3) that is missing or not of the quantity's
// kind. Units are converted, never guessed.
std::optional<Result<LiveQuantity>> live_quantity(std::string_view browse_path, std::string_view unit,
                                                  const historian::Value& value);

}  // namespace sf::cloud::detail
