#include "opcua_values.hpp"

#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace sf::app {

namespace ua = sf::opcua;
using nlohmann::json;

ua::BuiltinType builtin_type_of_data_type(const ua::NodeId& data_type) {
  if (data_type.namespace_index != 0 || data_type.type() != ua::NodeIdType::Numeric) {
    return ua::BuiltinType::Null;
  }
  const std::uint32_t id = data_type.numeric();
  // DataType NodeIds 1..25 of namespace 0 are the built-in types themselves (OPC 10000-6 §5.1.2).
  if (id >= 1 && id <= 25) {
    return static_cast<ua::BuiltinType>(id);
  }
  if (id == ua::id::Enumeration) {
    return ua::BuiltinType::Int32;
  }
  return ua::BuiltinType::Null;
}

namespace {

template <typename T>
Result<ua::Variant> parse_number(std::string_view text) {
  T value{};
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end) {
    return make_error(Errc::invalid_argument,
                      fmt::format("'{}' is not a number of this type or is out of its range", text));
  }
  return ua::Variant(value);
}

Result<ua::Variant> parse_bool(std::string_view text) {
  if (text == "true" || text == "1") {
    return ua::Variant(true);
  }
  if (text == "false" || text == "0") {
    return ua::Variant(false);
  }
  return make_error(Errc::invalid_argument, fmt::format("'{}' is not a Boolean (true/false)", text));
}

// "2024-05-01T12:00:00Z", with fractional seconds or a zone offset (xs:dateTime).
Result<ua::Variant> parse_date_time(std::string_view text) {
  auto parsed = ua::DateTime::parse(text);
  if (!parsed) {
    return make_error(Errc::invalid_argument, parsed.error().message);
  }
  return ua::Variant(*parsed);
}

Result<ua::Variant> parse_scalar(ua::BuiltinType type, std::string_view text) {
  using B = ua::BuiltinType;
  switch (type) {
    case B::Boolean:
      return parse_bool(text);
    case B::SByte:
      return parse_number<std::int8_t>(text);
    case B::Byte:
      return parse_number<std::uint8_t>(text);
    case B::Int16:
      return parse_number<std::int16_t>(text);
    case B::UInt16:
      return parse_number<std::uint16_t>(text);
    case B::Int32:
      return parse_number<std::int32_t>(text);
    case B::UInt32:
      return parse_number<std::uint32_t>(text);
    case B::Int64:
      return parse_number<std::int64_t>(text);
    case B::UInt64:
      return parse_number<std::uint64_t>(text);
    case B::Float:
      return parse_number<float>(text);
    case B::Double:
      return parse_number<double>(text);
    case B::String:
      return ua::Variant(ua::String(text));
    case B::DateTime:
      return parse_date_time(text);
    case B::ByteString: {
      auto bytes = from_hex(text);
      if (!bytes) {
        return bytes.error();
      }
      return ua::Variant(ua::ByteString(std::move(*bytes)));
    }
    case B::NodeId: {
      auto id = ua::NodeId::parse(text);
      if (!id) {
        return id.error();
      }
      return ua::Variant(std::move(*id));
    }
    case B::LocalizedText:
      return ua::Variant(ua::LocalizedText("", ua::String(text)));
    case B::QualifiedName:
      return ua::Variant(ua::QualifiedName(0, ua::String(text)));
    case B::StatusCode: {
      auto code = ua::status_code_from_name(text);
      if (!code) {
        return make_error(Errc::invalid_argument, fmt::format("'{}' is not a StatusCode name", text));
      }
      return ua::Variant(*code);
    }
    default:
      return make_error(
          Errc::invalid_argument,
          fmt::format("values of type {} cannot be given on the command line", ua::to_string(type)));
  }
}

template <typename T>
Result<ua::Variant> collect(const std::vector<ua::Variant>& items) {
  ua::Array<T> out;
  for (const auto& item : items) {
    out.push_back(*item.get_if<T>());
  }
  return ua::Variant(std::move(out));
}

Result<ua::Variant> parse_array(ua::BuiltinType type, std::string_view text) {
  const json parsed = json::parse(text, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_array()) {
    return make_error(Errc::invalid_argument, fmt::format("'{}' is not a JSON array", text));
  }
  std::vector<ua::Variant> items;
  for (const auto& element : parsed) {
    auto item = parse_scalar(type, element.is_string() ? element.get<std::string>() : element.dump());
    if (!item) {
      return item.error();
    }
    items.push_back(std::move(*item));
  }
  using B = ua::BuiltinType;
  switch (type) {
    case B::Boolean:
      return collect<bool>(items);
    case B::SByte:
      return collect<std::int8_t>(items);
    case B::Byte:
      return collect<std::uint8_t>(items);
    case B::Int16:
      return collect<std::int16_t>(items);
    case B::UInt16:
      return collect<std::uint16_t>(items);
    case B::Int32:
      return collect<std::int32_t>(items);
    case B::UInt32:
      return collect<std::uint32_t>(items);
    case B::Int64:
      return collect<std::int64_t>(items);
    case B::UInt64:
      return collect<std::uint64_t>(items);
    case B::Float:
      return collect<float>(items);
    case B::Double:
      return collect<double>(items);
    case B::String:
      return collect<ua::String>(items);
    default:
      return make_error(Errc::invalid_argument,
                        fmt::format("arrays of {} are not supported", ua::to_string(type)));
  }
}

}  // namespace

Result<ua::Variant> parse_variant(ua::BuiltinType type, std::string_view text) {
  if (type == ua::BuiltinType::Null) {
    return make_error(Errc::invalid_argument,
                      "the node's DataType is not a built-in type; give one as TYPE:VALUE");
  }
  if (!text.empty() && text.front() == '[') {
    return parse_array(type, text);
  }
  return parse_scalar(type, text);
}

Result<ua::Variant> parse_typed_variant(std::string_view text, ua::BuiltinType fallback) {
  const auto colon = text.find(':');
  if (colon != std::string_view::npos) {
    const auto name = text.substr(0, colon);
    for (std::uint8_t i = 1; i <= 25; ++i) {
      const auto type = static_cast<ua::BuiltinType>(i);
      if (ua::to_string(type) == name) {
        return parse_variant(type, text.substr(colon + 1));
      }
    }
  }
  return parse_variant(fallback, text);
}

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

Result<NodeRef> parse_node_ref(std::string_view text) {
  NodeRef ref;
  if (text.starts_with("nsu=")) {
    const auto semi = text.find(';');
    if (semi == std::string_view::npos) {
      return make_error(Errc::invalid_argument,
                        fmt::format("'{}': nsu=URI must be followed by ;i=, ;s=, ...", text));
    }
    ref.namespace_uri = std::string(text.substr(4, semi - 4));
    text = text.substr(semi + 1);
  }
  auto id = ua::NodeId::parse(text);
  if (!id) {
    return id.error();
  }
  ref.node_id = std::move(*id);
  return ref;
}

}  // namespace sf::app
