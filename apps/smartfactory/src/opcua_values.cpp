#include "opcua_values.hpp"

#include <cmath>

#include <fmt/format.h>

namespace sf::app {

namespace ua = sf::opcua;
using nlohmann::json;

namespace {

template <typename T>
json scalar_to_json(const T& value) {
  if constexpr (std::is_same_v<T, bool> || std::is_arithmetic_v<T>) {
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(value)) {
        return fmt::format("{}", value);
      }
    }
    return value;
  } else if constexpr (std::is_same_v<T, ua::String>) {
    return value.str();
  } else if constexpr (std::is_same_v<T, ua::LocalizedText>) {
    return value.text.str();
  } else if constexpr (std::is_same_v<T, ua::Variant>) {
    return variant_to_json(value);
  } else if constexpr (std::is_same_v<T, ua::StatusCode>) {
    return ua::to_string(value);
  } else {
    return ua::to_string(value);
  }
}

}  // namespace

json variant_to_json(const ua::Variant& value) {
  return std::visit(
      [](const auto& stored) -> json {
        using S = std::decay_t<decltype(stored)>;
        if constexpr (std::is_same_v<S, std::monostate>) {
          return nullptr;
        } else if constexpr (requires {
                               typename S::value_type;
                               stored.size();
                             } &&
                             !std::is_same_v<S, ua::String> && !std::is_same_v<S, ua::ByteString>) {
          json array = json::array();
          for (const auto& element : stored) {
            if constexpr (std::is_same_v<std::decay_t<decltype(element)>, bool>) {
              array.push_back(static_cast<bool>(element));
            } else {
              array.push_back(scalar_to_json(element));
            }
          }
          return array;
        } else if constexpr (requires { stored.get(); }) {
          return ua::to_string(*stored);  // boxed: ExpandedNodeId, ExtensionObject, ...
        } else {
          return scalar_to_json(stored);
        }
      },
      value.storage());
}

json data_value_to_json(const ua::DataValue& value) {
  json out;
  out["value"] = variant_to_json(value.value);
  out["type"] = std::string(ua::to_string(value.value.type()));
  out["status"] = ua::to_string(value.status);
  if (value.source_timestamp != ua::DateTime{}) {
    out["sourceTimestamp"] = ua::to_string(value.source_timestamp);
  }
  if (value.server_timestamp != ua::DateTime{}) {
    out["serverTimestamp"] = ua::to_string(value.server_timestamp);
  }
  return out;
}

}  // namespace sf::app
