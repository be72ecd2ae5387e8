// Writing the XML encoding of OPC 10000-6 §5.3 (see xml_codec.hpp).
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "sf/opcua/binary.hpp"
#include "xml_codec.hpp"
#include "xml_types.hpp"

namespace sf::opcua::server::nodeset {

namespace {

std::string prefixed(std::string_view name) {
  return fmt::format("uax:{}", name);
}

template <typename T>
std::string float_text(T value) {
  // xs:float/xs:double: INF, -INF, NaN; otherwise the shortest text that reads back exactly.
  if (std::isnan(value)) {
    return "NaN";
  }
  if (std::isinf(value)) {
    return value < 0 ? "-INF" : "INF";
  }
  return fmt::format("{}", value);
}

}  // namespace

struct EncodeVisitor {
  const XmlEncoder& encoder;

  // Appends <name>value</name> under parent.
  template <typename T>
  void write(pugi::xml_node parent, std::string_view name, const T& value) {
    pugi::xml_node e = parent.append_child(prefixed(name).c_str());
    write_content(e, value);
  }

  template <typename T>
  void write_content(pugi::xml_node e, const T& value) {
    if constexpr (std::is_same_v<T, bool>) {
      e.text().set(value ? "true" : "false");
    } else if constexpr (std::is_floating_point_v<T>) {
      e.text().set(float_text(value).c_str());
    } else if constexpr (std::is_integral_v<T>) {
      e.text().set(std::to_string(value).c_str());
    } else if constexpr (std::is_enum_v<T>) {
      // OPC 10000-6 §5.3.4: "<symbol>_<value>".
      const auto number = static_cast<std::int32_t>(value);
      const std::string symbol = to_string(value);
      e.text().set(symbol.find('(') == std::string::npos ? fmt::format("{}_{}", symbol, number).c_str()
                                                         : std::to_string(number).c_str());
    } else if constexpr (IsArray<T>::value) {
      using Element = typename IsArray<T>::Element;
      for (const auto& item : value) {
        write(e, element_name<Element>(), item);
      }
    } else if constexpr (Structure<T>) {
      visit_fields(value, [&](std::string_view field, const auto& member) {
        write(e, field_element_name(field), member);
      });
    } else {
      write_builtin(e, value);
    }
  }

  void write_builtin(pugi::xml_node e, const String& value) {
    if (value.is_null()) {
      e.append_attribute("xsi:nil").set_value("true");
    } else {
      e.text().set(value.str().c_str());
    }
  }
  void write_builtin(pugi::xml_node e, DateTime value) { e.text().set(to_string(value).c_str()); }
  void write_builtin(pugi::xml_node e, const Guid& value) { write(e, "String", String(to_string(value))); }
  void write_builtin(pugi::xml_node e, const ByteString& value) {
    e.text().set(base64_encode(value.span()).c_str());
  }
  void write_builtin(pugi::xml_node e, const XmlElement& value) {
    pugi::xml_document fragment;
    if (fragment.load_string(value.xml.str().c_str())) {
      for (pugi::xml_node child = fragment.first_child(); child; child = child.next_sibling()) {
        e.append_copy(child);
      }
    }
  }
  void write_builtin(pugi::xml_node e, const NodeId& value) {
    if (!value.is_null()) {
      write(e, "Identifier", String(encoder.node_id(value)));
    }
  }
  void write_builtin(pugi::xml_node e, const ExpandedNodeId& value) { write_builtin(e, value.node_id); }
  void write_builtin(pugi::xml_node e, StatusCode value) { write(e, "Code", value.value()); }
  void write_builtin(pugi::xml_node e, const QualifiedName& value) {
    write(e, "NamespaceIndex", encoder.ns_.map(value.namespace_index).value_or(0));
    write(e, "Name", value.name);
  }
  void write_builtin(pugi::xml_node e, const LocalizedText& value) {
    if (!value.locale.is_null()) {
      write(e, "Locale", value.locale);
    }
    if (!value.text.is_null()) {
      write(e, "Text", value.text);
    }
  }
  void write_builtin(pugi::xml_node e, const ExtensionObject& value) {
    pugi::xml_node type = e.append_child("uax:TypeId");
    // A structure with an XML form is tagged with its DataTypeEncoding "Default XML".
    const bool known = any_xml_structure([&](auto tag) {
      using T = typename decltype(tag)::type;
      const T* typed = value.get_if<T>();
      if (typed != nullptr) {
        write_builtin(type, NodeId(0, T::kXmlEncodingId));
        write(e.append_child("uax:Body"), T::kTypeName, *typed);
      }
      return typed != nullptr;
    });
    if (known) {
      return;
    }
    write_builtin(type, value.type_id());
    if (value.empty()) {
      return;
    }
    pugi::xml_node body = e.append_child("uax:Body");
    if (const XmlElement* xml = value.xml_body()) {
      write_builtin(body, *xml);
    } else if (const ByteString* bytes = value.opaque_body()) {
      // No XML form here: the binary body, as OPC 10000-6 §5.3.1.16 allows.
      write(body, "ByteString", *bytes);
    }
  }
  void write_builtin(pugi::xml_node e, const Variant& value) { write_variant(e, value); }
  void write_builtin(pugi::xml_node /*e*/, const DataValue& /*value*/) {}
  void write_builtin(pugi::xml_node /*e*/, const DiagnosticInfo& /*value*/) {}

  // The value's element(s) under holder (<Value> or <Variant>).
  void write_variant(pugi::xml_node holder, const Variant& value) {
    if (value.is_empty()) {
      return;
    }
    const std::string_view type = to_string(value.type());
    std::visit(
        [&](const auto& stored) {
          using S = std::decay_t<decltype(stored)>;
          if constexpr (std::is_same_v<S, std::monostate>) {
            return;
          } else if constexpr (IsArray<S>::value) {
            if (value.is_matrix()) {
              pugi::xml_node matrix = holder.append_child("uax:Matrix");
              write(matrix, "Dimensions", Array<std::int32_t>(value.array_dimensions()));
              write(matrix, "Elements", stored);
            } else {
              write(holder, fmt::format("ListOf{}", type), stored);
            }
          } else if constexpr (requires { stored.get(); }) {
            write(holder, type, *stored);  // Box<T>
          } else {
            write(holder, type, stored);
          }
        },
        value.storage());
  }
};

void XmlEncoder::value(pugi::xml_node value_element, const Variant& value) const {
  EncodeVisitor{*this}.write_variant(value_element, value);
}

std::string XmlEncoder::node_id(const NodeId& id) const {
  NodeId mapped = id;
  mapped.namespace_index = ns_.map(id.namespace_index).value_or(0);
  return to_string(mapped);
}

std::string XmlEncoder::qualified_name(const QualifiedName& name) const {
  const std::uint16_t index = ns_.map(name.namespace_index).value_or(0);
  return index == 0 ? name.name.str() : fmt::format("{}:{}", index, name.name.str());
}

}  // namespace sf::opcua::server::nodeset
