// Reading the XML encoding of OPC 10000-6 §5.3 (see xml_codec.hpp).
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "sf/core/text.hpp"
#include "sf/opcua/binary.hpp"
#include "xml_codec.hpp"
#include "xml_types.hpp"

namespace sf::opcua::server::nodeset {

namespace {

// Values nest through ListOfVariant and ExtensionObjects; a file may not nest without end.
constexpr int kMaxDepth = 16;

std::string_view text_of(pugi::xml_node element) {
  return trim(element.child_value());
}

bool is_nil(pugi::xml_node element) {
  return element.attribute("xsi:nil").as_bool(false);
}

}  // namespace

std::optional<std::uint16_t> NamespaceMap::map(std::uint16_t index) const {
  if (index == 0) {
    return std::uint16_t{0};
  }
  if (index >= to_.size()) {
    return std::nullopt;
  }
  return to_[index];
}

std::string_view local_name(pugi::xml_node element) {
  std::string_view name = element.name();
  const auto colon = name.find(':');
  return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

pugi::xml_node child_element(pugi::xml_node parent, std::string_view name) {
  for (pugi::xml_node child = parent.first_child(); child; child = child.next_sibling()) {
    if (child.type() == pugi::node_element && local_name(child) == name) {
      return child;
    }
  }
  return {};
}

BuiltinType builtin_by_name(std::string_view name) {
  for (std::uint8_t id = 1; id <= static_cast<std::uint8_t>(BuiltinType::DiagnosticInfo); ++id) {
    if (to_string(static_cast<BuiltinType>(id)) == name) {
      return static_cast<BuiltinType>(id);
    }
  }
  return BuiltinType::Null;
}

std::string field_element_name(std::string_view field) {
  std::string name(field);
  if (!name.empty() && name[0] >= 'a' && name[0] <= 'z') {
    name[0] = static_cast<char>(name[0] - 'a' + 'A');
  }
  return name;
}

// One decoding pass; the first error stops it (every read returns false from then on).
struct DecodeVisitor {
  XmlDecoder& decoder;
  std::optional<Error> error;
  int depth = 0;

  bool fail(pugi::xml_node at, std::string message) {
    if (!error) {
      error = make_error(Errc::malformed, fmt::format("{}: {}", decoder.where_(at), message));
    }
    return false;
  }

  template <typename T>
  bool read(pugi::xml_node e, T& out) {
    if (error) {
      return false;
    }
    if constexpr (std::is_same_v<T, bool>) {
      return read_bool(e, out);
    } else if constexpr (std::is_integral_v<T>) {
      return read_integer(e, out);
    } else if constexpr (std::is_floating_point_v<T>) {
      return read_float(e, out);
    } else if constexpr (std::is_enum_v<T>) {
      return read_enum(e, out);
    } else if constexpr (IsArray<T>::value) {
      return read_array(e, out);
    } else if constexpr (Structure<T>) {
      return read_structure(e, out);
    } else {
      return read_builtin(e, out);
    }
  }

  bool read_bool(pugi::xml_node e, bool& out) {
    const auto text = text_of(e);
    if (text == "true" || text == "1") {
      out = true;
      return true;
    }
    if (text == "false" || text == "0") {
      out = false;
      return true;
    }
    return fail(e, fmt::format("'{}' is not a Boolean", text));
  }

  template <typename T>
  bool read_integer(pugi::xml_node e, T& out) {
    const auto text = text_of(e);
    const auto* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, out);
    if (ec != std::errc{} || ptr != end) {
      return fail(e, fmt::format("'{}' is not a {}", text, element_name<T>()));
    }
    return true;
  }

  template <typename T>
  bool read_float(pugi::xml_node e, T& out) {
    const std::string text(text_of(e));
    // xs:float/xs:double spell the specials INF, -INF and NaN.
    if (text == "INF" || text == "-INF" || text == "NaN") {
      out = text == "NaN"
                ? std::numeric_limits<T>::quiet_NaN()
                : (text[0] == '-' ? -std::numeric_limits<T>::infinity() : std::numeric_limits<T>::infinity());
      return true;
    }
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || std::isinf(value) || std::isnan(value)) {
      return fail(e, fmt::format("'{}' is not a {}", text, element_name<T>()));
    }
    out = static_cast<T>(value);
    return true;
  }

  // OPC 10000-6 §5.3.4: "<symbol>_<value>"; a bare number is accepted too.
  template <typename T>
  bool read_enum(pugi::xml_node e, T& out) {
    auto text = text_of(e);
    const auto underscore = text.rfind('_');
    if (underscore != std::string_view::npos) {
      text = text.substr(underscore + 1);
    }
    std::int32_t value = 0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc{} || ptr != text.data() + text.size()) {
      return fail(e, fmt::format("'{}' is not an enumeration value (Name_<n>)", text_of(e)));
    }
    out = static_cast<T>(value);
    return true;
  }

  template <typename T>
  bool read_array(pugi::xml_node e, Array<T>& out) {
    out.clear();
    for (pugi::xml_node item = e.first_child(); item; item = item.next_sibling()) {
      if (item.type() != pugi::node_element) {
        continue;
      }
      T value{};
      if (!read(item, value)) {
        return false;
      }
      out.push_back(std::move(value));
    }
    return true;
  }

  template <typename T>
  bool read_structure(pugi::xml_node e, T& out) {
    bool ok = true;
    visit_fields(out, [&](std::string_view field, auto& member) {
      if (ok) {
        // Absent fields keep their defaults: writers omit null and default fields.
        const pugi::xml_node child = child_element(e, field_element_name(field));
        ok = !child || read(child, member);
      }
    });
    return ok;
  }

  bool read_builtin(pugi::xml_node e, String& out) {
    if (is_nil(e)) {
      out.set_null();
    } else {
      out = String(std::string_view(e.child_value()));
    }
    return true;
  }

  bool read_builtin(pugi::xml_node e, DateTime& out) {
    auto parsed = DateTime::parse(text_of(e));
    if (!parsed) {
      return fail(e, parsed.error().message);
    }
    out = *parsed;
    return true;
  }

  bool read_builtin(pugi::xml_node e, Guid& out) {
    const pugi::xml_node text = child_element(e, "String");
    auto parsed = Guid::parse(text ? text_of(text) : text_of(e));
    if (!parsed) {
      return fail(e, parsed.error().message);
    }
    out = *parsed;
    return true;
  }

  bool read_builtin(pugi::xml_node e, ByteString& out) {
    std::string compact;
    for (const char c : std::string_view(e.child_value())) {
      if (c != ' ' && c != '\t' && c != '\r' && c != '\n') {
        compact.push_back(c);
      }
    }
    auto bytes = base64_decode(compact);
    if (!bytes) {
      return fail(e, "ByteString is not base64: " + bytes.error().message);
    }
    out = ByteString(std::move(*bytes));
    return true;
  }

  bool read_builtin(pugi::xml_node e, XmlElement& out) {
    std::ostringstream xml;
    for (pugi::xml_node child = e.first_child(); child; child = child.next_sibling()) {
      child.print(xml, "", pugi::format_raw);
    }
    out.xml = String(xml.str());
    return true;
  }

  bool read_builtin(pugi::xml_node e, NodeId& out) {
    const pugi::xml_node identifier = child_element(e, "Identifier");
    const auto text = identifier ? text_of(identifier) : std::string_view{};
    if (text.empty()) {
      out = NodeId{};
      return true;
    }
    auto parsed = decoder.node_id(e, text);
    if (!parsed) {
      error = parsed.error();
      return false;
    }
    out = std::move(*parsed);
    return true;
  }

  bool read_builtin(pugi::xml_node e, ExpandedNodeId& out) {
    NodeId local;
    if (!read_builtin(e, local)) {
      return false;
    }
    out = ExpandedNodeId(std::move(local));
    return true;
  }

  bool read_builtin(pugi::xml_node e, StatusCode& out) {
    std::uint32_t code = 0;
    const pugi::xml_node child = child_element(e, "Code");
    if (child && !read_integer(child, code)) {
      return false;
    }
    out = StatusCode(code);
    return true;
  }

  bool read_builtin(pugi::xml_node e, QualifiedName& out) {
    std::uint16_t index = 0;
    const pugi::xml_node ns = child_element(e, "NamespaceIndex");
    if (ns && !read_integer(ns, index)) {
      return false;
    }
    const auto mapped = decoder.ns_.map(index);
    if (!mapped) {
      return fail(e, fmt::format("namespace index {} is not in the NamespaceUris table", index));
    }
    out.namespace_index = *mapped;
    return read_builtin(child_element(e, "Name"), out.name);
  }

  bool read_builtin(pugi::xml_node e, LocalizedText& out) {
    if (const pugi::xml_node locale = child_element(e, "Locale")) {
      read_builtin(locale, out.locale);
    }
    if (const pugi::xml_node text = child_element(e, "Text")) {
      read_builtin(text, out.text);
    }
    return true;
  }

  bool read_builtin(pugi::xml_node e, ExtensionObject& out) {
    NodeId type_id;
    if (const pugi::xml_node type = child_element(e, "TypeId"); type && !read_builtin(type, type_id)) {
      return false;
    }
    const pugi::xml_node body_holder = child_element(e, "Body");
    const pugi::xml_node body = body_holder ? body_holder.first_child() : pugi::xml_node{};
    if (!body || body.type() != pugi::node_element) {
      out = ExtensionObject(type_id, nullptr);
      return true;
    }
    bool ok = true;
    const bool known = any_xml_structure([&](auto tag) {
      using T = typename decltype(tag)::type;
      if (local_name(body) != T::kTypeName) {
        return false;
      }
      T value{};
      ok = read_structure(body, value);
      out = ExtensionObject::make(std::move(value));
      return true;
    });
    if (!known) {
      // A structure this stack has no type for stays XML (OPC 10000-6 §5.3.1.16).
      XmlElement xml;
      std::ostringstream text;
      body.print(text, "", pugi::format_raw);
      xml.xml = String(text.str());
      out = ExtensionObject::xml(type_id, std::move(xml));
    }
    return ok;
  }

  bool read_builtin(pugi::xml_node e, Variant& out) {
    if (++depth > kMaxDepth) {
      return fail(e, fmt::format("values nest deeper than {} levels", kMaxDepth));
    }
    const bool ok = read_variant(e, out);
    --depth;
    return ok;
  }

  bool read_builtin(pugi::xml_node e, DataValue& /*out*/) {
    return fail(e, "DataValue values are not supported in NodeSet2 files");
  }
  bool read_builtin(pugi::xml_node e, DiagnosticInfo& /*out*/) {
    return fail(e, "DiagnosticInfo values are not supported in NodeSet2 files");
  }

  // holder: <Value> or <Variant>; its first child element is the value.
  bool read_variant(pugi::xml_node holder, Variant& out) {
    pugi::xml_node e = holder.first_child();
    while (e && e.type() != pugi::node_element) {
      e = e.next_sibling();
    }
    if (!e) {
      out = Variant{};
      return true;
    }
    const std::string_view name = local_name(e);
    if (name == "Matrix") {
      return read_matrix(e, out);
    }
    const bool list = name.starts_with("ListOf");
    const BuiltinType type = builtin_by_name(list ? name.substr(6) : name);
    if (type == BuiltinType::Null || (!list && type == BuiltinType::Variant)) {
      return fail(e, fmt::format("<{}> is not a value type of OPC 10000-6 §5.3.1", name));
    }
    bool ok = true;
    with_builtin(type, [&](auto tag) {
      using T = typename decltype(tag)::type;
      if (list) {
        Array<T> values;
        ok = read_array(e, values);
        out = Variant(std::move(values));
      } else if constexpr (!std::is_same_v<T, Variant>) {
        T value{};
        ok = read(e, value);
        out = Variant(std::move(value));
      }
    });
    return ok;
  }

  // <Matrix><Dimensions><Int32>2</Int32>...</Dimensions><Elements><Double>...</Elements></Matrix>
  bool read_matrix(pugi::xml_node e, Variant& out) {
    Array<std::int32_t> dimensions;
    if (!read_array(child_element(e, "Dimensions"), dimensions)) {
      return false;
    }
    const pugi::xml_node elements = child_element(e, "Elements");
    pugi::xml_node first = elements.first_child();
    while (first && first.type() != pugi::node_element) {
      first = first.next_sibling();
    }
    const BuiltinType type = first ? builtin_by_name(local_name(first)) : BuiltinType::Null;
    if (type == BuiltinType::Null || type == BuiltinType::Variant) {
      return fail(e, "a Matrix needs <Elements> of one built-in type");
    }
    bool ok = true;
    with_builtin(type, [&](auto tag) {
      using T = typename decltype(tag)::type;
      Array<T> values;
      ok = read_array(elements, values);
      if (ok) {
        auto matrix = Variant::matrix(std::move(values), dimensions);
        ok = matrix.ok() ? (out = std::move(*matrix), true) : fail(e, matrix.error().message);
      }
    });
    return ok;
  }
};

Result<Variant> XmlDecoder::value(pugi::xml_node value_element) {
  DecodeVisitor visitor{*this, std::nullopt};
  Variant out;
  if (!visitor.read_variant(value_element, out)) {
    return *visitor.error;
  }
  return out;
}

Result<NodeId> XmlDecoder::node_id(pugi::xml_node at, std::string_view text) {
  auto parsed = NodeId::parse(trim(text));
  if (!parsed) {
    return make_error(Errc::malformed, fmt::format("{}: {}", where_(at), parsed.error().message));
  }
  const auto mapped = ns_.map(parsed->namespace_index);
  if (!mapped) {
    return make_error(Errc::malformed,
                      fmt::format("{}: namespace index {} of {} is not in the NamespaceUris table",
                                  where_(at), parsed->namespace_index, text));
  }
  parsed->namespace_index = *mapped;
  return parsed;
}

Result<QualifiedName> XmlDecoder::qualified_name(pugi::xml_node at, std::string_view text) {
  // OPC 10000-6 §F.5: "<index>:<name>", or the name alone in namespace 0.
  const auto colon = text.find(':');
  std::uint16_t index = 0;
  std::string_view name = text;
  if (colon != std::string_view::npos) {
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + colon, index);
    if (ec == std::errc{} && ptr == text.data() + colon) {
      name = text.substr(colon + 1);
    } else {
      index = 0;  // a colon inside a namespace-0 name
    }
  }
  const auto mapped = ns_.map(index);
  if (!mapped) {
    return make_error(Errc::malformed, fmt::format("{}: namespace index {} of BrowseName '{}' is not in the "
                                                   "NamespaceUris table",
                                                   where_(at), index, text));
  }
  if (name.empty()) {
    return make_error(Errc::malformed, fmt::format("{}: empty BrowseName", where_(at)));
  }
  return QualifiedName(*mapped, String(name));
}

}  // namespace sf::opcua::server::nodeset
