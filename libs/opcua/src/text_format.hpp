// Text of generated structures for logs and test output: "ReadValueId{nodeId=i=2258, ...}".
#pragma once

#include <string>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>

#include "sf/opcua/binary.hpp"
#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/variant.hpp"

namespace sf::opcua {

template <typename T>
std::string field_text(const T& value);

template <typename T>
std::string array_field_text(const Array<T>& values) {
  if (values.is_null()) {
    return "null";
  }
  constexpr std::size_t kShown = 8;
  std::string out = "[";
  for (std::size_t i = 0; i < values.size() && i < kShown; ++i) {
    out += i == 0 ? "" : ", ";
    out += field_text(static_cast<const T&>(values[i]));
  }
  if (values.size() > kShown) {
    out += fmt::format(", ... ({} elements)", values.size());
  }
  return out + "]";
}

template <typename T>
std::string field_text(const T& value) {
  if constexpr (std::is_same_v<T, bool>) {
    return value ? "true" : "false";
  } else if constexpr (std::is_same_v<T, std::int8_t> || std::is_same_v<T, std::uint8_t>) {
    return std::to_string(static_cast<int>(value));
  } else if constexpr (std::is_arithmetic_v<T>) {
    return fmt::format("{}", value);
  } else if constexpr (requires {
                         value.is_null();
                         value.begin();
                       }) {
    return array_field_text(value);
  } else {
    return to_string(value);
  }
}

template <typename S>
std::string structure_text(const S& value) {
  std::string out(S::kTypeName);
  out += '{';
  bool first = true;
  visit_fields(value, [&](std::string_view name, const auto& field) {
    out += first ? "" : ", ";
    first = false;
    out += name;
    out += '=';
    out += field_text(field);
  });
  return out + "}";
}

}  // namespace sf::opcua
