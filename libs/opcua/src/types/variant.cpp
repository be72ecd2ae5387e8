#include "sf/opcua/variant.hpp"

#include <ostream>

#include <fmt/format.h>

#include "opcua_internal.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

// ---- ExtensionObject --------------------------------------------------------------------------

ExtensionObject::ExtensionObject(NodeId type_id, std::unique_ptr<ExtensionBody> body)
    : type_id_(std::move(type_id)) {
  if (body) {
    body_ = std::move(body);
  }
}

ExtensionObject::ExtensionObject(const ExtensionObject& other) : type_id_(other.type_id_) {
  if (const auto* typed = other.body()) {
    body_ = typed->clone();
  } else if (const auto* bytes = other.opaque_body()) {
    body_ = *bytes;
  } else if (const auto* xml = other.xml_body()) {
    body_ = *xml;
  }
}

ExtensionObject& ExtensionObject::operator=(const ExtensionObject& other) {
  if (this != &other) {
    ExtensionObject copy(other);
    *this = std::move(copy);
  }
  return *this;
}

ExtensionObject::~ExtensionObject() = default;

ExtensionObject ExtensionObject::opaque(NodeId type_id, ByteString body) {
  ExtensionObject eo;
  eo.type_id_ = std::move(type_id);
  eo.body_ = std::move(body);
  return eo;
}

ExtensionObject ExtensionObject::xml(NodeId type_id, XmlElement body) {
  ExtensionObject eo;
  eo.type_id_ = std::move(type_id);
  eo.body_ = std::move(body);
  return eo;
}

ExtensionObject::Encoding ExtensionObject::encoding() const {
  switch (body_.index()) {
    case 0:
      return Encoding::None;
    case 2:
      return Encoding::Xml;
    default:
      return Encoding::Binary;
  }
}

const ExtensionBody* ExtensionObject::body() const {
  const auto* holder = std::get_if<std::unique_ptr<ExtensionBody>>(&body_);
  return holder != nullptr ? holder->get() : nullptr;
}

bool operator==(const ExtensionObject& a, const ExtensionObject& b) {
  if (a.type_id_ != b.type_id_ || a.body_.index() != b.body_.index()) {
    return false;
  }
  if (a.is_decoded()) {
    return a.body()->equals(*b.body());
  }
  if (const auto* bytes = a.opaque_body()) {
    return *bytes == *b.opaque_body();
  }
  if (const auto* xml = a.xml_body()) {
    return *xml == *b.xml_body();
  }
  return true;
}

// ---- Variant ----------------------------------------------------------------------------------

BuiltinType Variant::type() const {
  std::size_t i = storage_.index();
  if (i >= kFirstArrayIndex) {
    i -= kFirstArrayIndex - 1;  // arrays are ids 1..25
  } else if (i == kFirstArrayIndex - 1) {
    i = static_cast<std::size_t>(BuiltinType::DiagnosticInfo);  // scalars skip id 24 (Variant)
  }
  return static_cast<BuiltinType>(i);
}

std::size_t Variant::array_length() const {
  if (is_empty()) {
    return 0;
  }
  if (is_scalar()) {
    return 1;
  }
  return std::visit(
      [](const auto& v) -> std::size_t {
        if constexpr (requires { v.size(); }) {
          return v.size();
        } else {
          return 1;
        }
      },
      storage_);
}

namespace {

// Product of the dimensions, or 0 when one of them is <= 0 (OPC 10000-6 §5.2.2.16); stops early
// (returning limit + 1) once it exceeds limit so that it cannot overflow.
std::size_t dimensions_product(const std::vector<std::int32_t>& dims, std::size_t limit) {
  std::size_t product = 1;
  for (std::int32_t d : dims) {
    if (d <= 0) {
      return 0;
    }
    const auto u = static_cast<std::size_t>(d);
    if (product > limit / u) {
      return limit + 1;
    }
    product *= u;
  }
  return product;
}

}  // namespace

Status Variant::set_array_dimensions(std::vector<std::int32_t> dimensions) {
  if (!dimensions.empty()) {
    if (!is_array()) {
      return status_error(status::BadEncodingError, "array dimensions on a Variant that holds no array");
    }
    const std::size_t n = array_length();
    const std::size_t product = dimensions_product(dimensions, n);
    if (product != n) {
      return status_error(
          status::BadEncodingError,
          fmt::format("array dimensions [{}] do not match the {} element(s)", fmt::join(dimensions, ","), n));
    }
  }
  dimensions_ = std::move(dimensions);
  return {};
}

bool dimensions_match(const std::vector<std::int32_t>& dimensions, std::size_t length) {
  return dimensions_product(dimensions, length) == length;
}

// ---- to_string --------------------------------------------------------------------------------

namespace {

std::string scalar_text(const auto& v) {
  using T = std::decay_t<decltype(v)>;
  if constexpr (std::is_same_v<T, bool>) {
    return v ? "true" : "false";
  } else if constexpr (std::is_same_v<T, std::int8_t> || std::is_same_v<T, std::uint8_t>) {
    return std::to_string(static_cast<int>(v));
  } else if constexpr (std::is_arithmetic_v<T>) {
    return fmt::format("{}", v);
  } else {
    return to_string(v);
  }
}

template <typename T>
std::string array_text(const Array<T>& values) {
  if (values.is_null()) {
    return "null";
  }
  constexpr std::size_t kShown = 16;
  std::string out = "[";
  for (std::size_t i = 0; i < values.size() && i < kShown; ++i) {
    if (i != 0) {
      out += ", ";
    }
    out += scalar_text(static_cast<const T&>(values[i]));
  }
  if (values.size() > kShown) {
    out += fmt::format(", ... ({} elements)", values.size());
  }
  return out + "]";
}

}  // namespace

std::string to_string(const Variant& value) {
  if (value.is_empty()) {
    return "Null";
  }
  std::string body = std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return "";
        } else if constexpr (requires {
                               v.is_null();
                               v.begin();
                             }) {
          return array_text(v);
        } else if constexpr (requires {
                               v.get();
                               v.has_value();
                             }) {
          return v ? scalar_text(*v) : "null";
        } else {
          return scalar_text(v);
        }
      },
      value.storage());
  std::string type(to_string(value.type()));
  if (value.is_matrix()) {
    type += fmt::format("[{}]", fmt::join(value.array_dimensions(), ","));
  } else if (value.is_array()) {
    type += "[]";
  }
  return fmt::format("{}:{}", type, body);
}

std::string to_string(const DataValue& value) {
  std::string out = "DataValue{";
  out += to_string(value.value);
  if (value.status != StatusCode{}) {
    out += ", status=" + to_string(value.status);
  }
  if (value.source_timestamp.ticks() != 0 || value.source_picoseconds != 0) {
    out += ", source=" + to_string(value.source_timestamp);
    if (value.source_picoseconds != 0) {
      out += fmt::format("+{}0ps", value.source_picoseconds);
    }
  }
  if (value.server_timestamp.ticks() != 0 || value.server_picoseconds != 0) {
    out += ", server=" + to_string(value.server_timestamp);
    if (value.server_picoseconds != 0) {
      out += fmt::format("+{}0ps", value.server_picoseconds);
    }
  }
  return out + "}";
}

std::string to_string(const DiagnosticInfo& value) {
  std::string out = "DiagnosticInfo{";
  const auto field = [&out](std::string_view name, std::int32_t index) {
    if (index != -1) {
      out += fmt::format("{}{}={}", out.back() == '{' ? "" : ", ", name, index);
    }
  };
  field("symbolicId", value.symbolic_id);
  field("namespaceUri", value.namespace_uri);
  field("locale", value.locale);
  field("localizedText", value.localized_text);
  const auto sep = [&out] { return out.back() == '{' ? "" : ", "; };
  if (!value.additional_info.is_null()) {
    out += fmt::format("{}additionalInfo={}", sep(), to_string(value.additional_info));
  }
  if (value.inner_status_code != StatusCode{}) {
    out += fmt::format("{}innerStatusCode={}", sep(), to_string(value.inner_status_code));
  }
  if (value.inner_diagnostic_info) {
    out += fmt::format("{}inner={}", sep(), to_string(*value.inner_diagnostic_info));
  }
  return out + "}";
}

std::string to_string(const ExtensionObject& value) {
  if (const auto* typed = value.body()) {
    return typed->to_string();
  }
  if (const auto* bytes = value.opaque_body()) {
    return fmt::format("ExtensionObject{{{}, {}}}", to_string(value.type_id()), to_string(*bytes));
  }
  if (const auto* xml = value.xml_body()) {
    return fmt::format("ExtensionObject{{{}, xml={}}}", to_string(value.type_id()), to_string(*xml));
  }
  return value.type_id().is_null() ? "ExtensionObject{}"
                                   : fmt::format("ExtensionObject{{{}}}", to_string(value.type_id()));
}

std::ostream& operator<<(std::ostream& os, const DiagnosticInfo& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const ExtensionObject& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const Variant& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const DataValue& value) {
  return os << to_string(value);
}

}  // namespace sf::opcua
