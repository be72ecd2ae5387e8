// JSON forms of OPC UA values for the `opcua` commands' --json output (what a user types is
// parsed by sf/opcua/value_text.hpp).
#pragma once

#include <nlohmann/json.hpp>

#include "sf/opcua/encoding.hpp"

namespace sf::app {

// A JSON value: numbers, booleans and strings as themselves, arrays as arrays, everything else
// as its text form.
nlohmann::json variant_to_json(const opcua::Variant& value);
nlohmann::json data_value_to_json(const opcua::DataValue& value);

}  // namespace sf::app
