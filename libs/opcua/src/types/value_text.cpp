#include "sf/opcua/value_text.hpp"

#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

using nlohmann::json;

BuiltinType builtin_type_of_ns0(const NodeId& data_type) {
  if (data_type.namespace_index != 0 || data_type.type() != NodeIdType::Numeric) {
    return BuiltinType::Null;
  }
  const std::uint32_t id = data_type.numeric();
  // DataType NodeIds 1..25 of namespace 0 are the built-in types themselves (OPC 10000-6 §5.1.2).
  if (id >= 1 && id <= 25) {
    return static_cast<BuiltinType>(id);
  }
  if (id == id::Enumeration) {
    return BuiltinType::Int32;
  }
  return BuiltinType::Null;
}

namespace {

template <typename T>
Result<Variant> parse_number(std::string_view text) {
  T value{};
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end) {
    return make_error(Errc::invalid_argument,
                      fmt::format("'{}' is not a number of this type or is out of its range", text));
  }
  return Variant(value);
}

Result<Variant> parse_bool(std::string_view text) {
  if (text == "true" || text == "1") {
    return Variant(true);
  }
  if (text == "false" || text == "0") {
    return Variant(false);
  }
  return make_error(Errc::invalid_argument, fmt::format("'{}' is not a Boolean (true/false)", text));
}

// "2024-05-01T12:00:00Z", with fractional seconds or a zone offset (xs:dateTime).
Result<Variant> parse_date_time(std::string_view text) {
  auto parsed = DateTime::parse(text);
  if (!parsed) {
    return make_error(Errc::invalid_argument, parsed.error().message);
  }
  return Variant(*parsed);
}

Result<Variant> parse_scalar(BuiltinType type, std::string_view text) {
  using B = BuiltinType;
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
      return Variant(String(text));
    case B::DateTime:
      return parse_date_time(text);
    case B::ByteString: {
      auto bytes = from_hex(text);
      if (!bytes) {
        return bytes.error();
      }
      return Variant(ByteString(std::move(*bytes)));
    }
    case B::NodeId: {
      auto id = NodeId::parse(text);
      if (!id) {
        return id.error();
      }
      return Variant(std::move(*id));
    }
    case B::LocalizedText:
      return Variant(LocalizedText("", String(text)));
    case B::QualifiedName:
      return Variant(QualifiedName(0, String(text)));
    case B::StatusCode: {
      auto code = status_code_from_name(text);
      if (!code) {
        return make_error(Errc::invalid_argument, fmt::format("'{}' is not a StatusCode name", text));
      }
      return Variant(*code);
    }
    default:
      return make_error(
          Errc::invalid_argument,
          fmt::format("values of type {} cannot be given on the command line", to_string(type)));
  }
}

template <typename T>
Result<Variant> collect(const std::vector<Variant>& items) {
  Array<T> out;
  for (const auto& item : items) {
    out.push_back(*item.get_if<T>());
  }
  return Variant(std::move(out));
}

Result<Variant> parse_array(BuiltinType type, std::string_view text) {
  const json parsed = json::parse(text, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_array()) {
    return make_error(Errc::invalid_argument, fmt::format("'{}' is not a JSON array", text));
  }
  std::vector<Variant> items;
  for (const auto& element : parsed) {
    auto item = parse_scalar(type, element.is_string() ? element.get<std::string>() : element.dump());
    if (!item) {
      return item.error();
    }
    items.push_back(std::move(*item));
  }
  using B = BuiltinType;
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
      return collect<String>(items);
    default:
      return make_error(Errc::invalid_argument,
                        fmt::format("arrays of {} are not supported", to_string(type)));
  }
}

}  // namespace

Result<Variant> parse_variant(BuiltinType type, std::string_view text) {
  if (type == BuiltinType::Null) {
    return make_error(Errc::invalid_argument,
                      "the node's DataType is not a built-in type; give one as TYPE:VALUE");
  }
  if (!text.empty() && text.front() == '[') {
    return parse_array(type, text);
  }
  return parse_scalar(type, text);
}

Result<Variant> parse_typed_variant(std::string_view text, BuiltinType fallback) {
  const auto colon = text.find(':');
  if (colon != std::string_view::npos) {
    const auto name = text.substr(0, colon);
    for (std::uint8_t i = 1; i <= 25; ++i) {
      const auto type = static_cast<BuiltinType>(i);
      if (to_string(type) == name) {
        return parse_variant(type, text.substr(colon + 1));
      }
    }
  }
  return parse_variant(fallback, text);
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
  auto id = NodeId::parse(text);
  if (!id) {
    return id.error();
  }
  ref.node_id = std::move(*id);
  return ref;
}

}  // namespace sf::opcua
