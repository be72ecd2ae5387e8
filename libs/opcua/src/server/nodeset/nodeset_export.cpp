// NodeSet2 export (OPC 10000-6 Annex F).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <set>
#include <sstream>

#include "sf/opcua/server/nodeset.hpp"
#include "xml_codec.hpp"
#include "xml_types.hpp"

namespace sf::opcua::server {

namespace {

constexpr const char* kNodeSetNamespace = "http://opcfoundation.org/UA/2011/03/UANodeSet.xsd";
constexpr const char* kTypesNamespace = "http://opcfoundation.org/UA/2008/02/Types.xsd";

const char* element_of(NodeClass node_class) {
  switch (node_class) {
    case NodeClass::Object:
      return "UAObject";
    case NodeClass::Variable:
      return "UAVariable";
    case NodeClass::Method:
      return "UAMethod";
    case NodeClass::ObjectType:
      return "UAObjectType";
    case NodeClass::VariableType:
      return "UAVariableType";
    case NodeClass::ReferenceType:
      return "UAReferenceType";
    case NodeClass::DataType:
      return "UADataType";
    case NodeClass::View:
      return "UAView";
    default:
      return nullptr;
  }
}

// Namespace indexes a value refers to (NodeIds and QualifiedNames, also inside the structures of
// ExtensionObjects): the exporter lists each in the file's NamespaceUris.
struct NamespaceCollector {
  std::set<std::uint16_t>& out;

  template <typename T>
  void add(const T& value) {
    if constexpr (std::is_same_v<T, NodeId> || std::is_same_v<T, QualifiedName>) {
      out.insert(value.namespace_index);
    } else if constexpr (std::is_same_v<T, ExpandedNodeId>) {
      out.insert(value.node_id.namespace_index);
    } else if constexpr (IsArray<T>::value) {
      for (const auto& item : value) {
        add(item);
      }
    } else if constexpr (nodeset::Structure<T>) {
      visit_fields(value, [&](std::string_view, const auto& member) { add(member); });
    } else if constexpr (std::is_same_v<T, ExtensionObject>) {
      add(value.type_id());
      nodeset::any_xml_structure([&](auto tag) {
        const auto* typed = value.template get_if<typename decltype(tag)::type>();
        if (typed != nullptr) {
          add(*typed);
        }
        return typed != nullptr;
      });
    } else if constexpr (std::is_same_v<T, Variant>) {
      std::visit(
          [&](const auto& stored) {
            using S = std::decay_t<decltype(stored)>;
            if constexpr (requires { stored.get(); }) {
              add(*stored);  // Box<T>
            } else if constexpr (!std::is_same_v<S, std::monostate>) {
              add(stored);
            }
          },
          value.storage());
    }
  }
};

class Exporter {
 public:
  Exporter(const AddressSpace& space, const NodeSetExportOptions& options)
      : space_(space), options_(options) {}

  Result<std::string> run() {
    SF_TRY(choose_namespaces());
    collect_nodes();
    build_namespace_table();
    write_header();
    write_aliases();
    for (const Node* node : nodes_) {
      write_node(*node);
    }
    std::ostringstream out;
    document_.save(out, "  ", pugi::format_indent, pugi::encoding_utf8);
    return out.str();
  }

 private:
  Status choose_namespaces() {
    if (options_.namespace_uris.empty()) {
      for (std::size_t i = 1; i < space_.namespaces().size(); ++i) {
        exported_.insert(static_cast<std::uint16_t>(i));
      }
      return {};
    }
    for (const std::string& uri : options_.namespace_uris) {
      const auto index = space_.namespace_index(uri);
      if (!index || *index == 0) {
        return make_error(Errc::not_found, fmt::format("namespace '{}' is not in the address space", uri));
      }
      exported_.insert(*index);
    }
    return {};
  }

  void collect_nodes() {
    space_.for_each_node([this](const Node& node) {
      if (exported_.contains(node.node_id.namespace_index)) {
        nodes_.push_back(&node);
      }
    });
    // Types before instances, then by NodeId: a stable, readable file.
    std::sort(nodes_.begin(), nodes_.end(), [](const Node* a, const Node* b) {
      const bool a_type = is_type(a->node_class());
      const bool b_type = is_type(b->node_class());
      if (a_type != b_type) {
        return a_type;
      }
      return to_string(a->node_id) < to_string(b->node_id);
    });
  }

  static bool is_type(NodeClass c) {
    return c == NodeClass::ObjectType || c == NodeClass::VariableType || c == NodeClass::ReferenceType ||
           c == NodeClass::DataType;
  }

  // The exported namespaces first, then every other one the nodes refer to (OPC 10000-6 §F.2).
  void build_namespace_table() {
    std::set<std::uint16_t> used;
    NamespaceCollector collect{used};
    for (const Node* node : nodes_) {
      collect.add(node->browse_name);
      for (const Reference& r : node->references) {
        collect.add(r.reference_type_id);
        collect.add(r.target_id);
      }
      if (const auto* variable = node->as<VariableNode>()) {
        collect.add(variable->data_type);
        collect.add(current_value(*variable).value);
      } else if (const auto* variable_type = node->as<VariableTypeNode>()) {
        collect.add(variable_type->data_type);
        collect.add(variable_type->value.value);
      }
    }
    std::vector<std::uint16_t> order(exported_.begin(), exported_.end());
    for (const std::uint16_t index : used) {
      if (index != 0 && !exported_.contains(index)) {
        order.push_back(index);
      }
    }
    std::vector<std::uint16_t> to(space_.namespaces().size(), 0);
    for (std::size_t i = 0; i < order.size(); ++i) {
      to[order[i]] = static_cast<std::uint16_t>(i + 1);
      file_namespaces_.push_back(space_.namespaces()[order[i]]);
    }
    map_ = nodeset::NamespaceMap(std::move(to));
  }

  static DataValue current_value(const VariableNode& variable) {
    return variable.reader ? variable.reader() : variable.value;
  }

  void write_header() {
    auto declaration = document_.append_child(pugi::node_declaration);
    declaration.append_attribute("version") = "1.0";
    declaration.append_attribute("encoding") = "utf-8";
    root_ = document_.append_child("UANodeSet");
    root_.append_attribute("xmlns") = kNodeSetNamespace;
    root_.append_attribute("xmlns:uax") = kTypesNamespace;
    root_.append_attribute("xmlns:xsi") = "http://www.w3.org/2001/XMLSchema-instance";
    root_.append_attribute("xmlns:xsd") = "http://www.w3.org/2001/XMLSchema";
    const std::string now = to_string(DateTime::from_system_clock(options_.clock->utc_now()));
    root_.append_attribute("LastModified") = now.c_str();
    pugi::xml_node uris = root_.append_child("NamespaceUris");
    for (const std::string& uri : file_namespaces_) {
      uris.append_child("Uri").text().set(uri.c_str());
    }
    pugi::xml_node models = root_.append_child("Models");
    for (const std::uint16_t index : exported_) {
      pugi::xml_node model = models.append_child("Model");
      model.append_attribute("ModelUri") = space_.namespaces()[index].c_str();
      model.append_attribute("Version") = options_.model_version.c_str();
      model.append_attribute("PublicationDate") = now.c_str();
      pugi::xml_node required = model.append_child("RequiredModel");
      required.append_attribute("ModelUri") = "http://opcfoundation.org/UA/";
      required.append_attribute("Version") = "1.04.0";
      required.append_attribute("PublicationDate") = "2019-05-01T00:00:00Z";
    }
  }

  // Aliases for the namespace-0 reference types and data types in use, named by their browse
  // names as the standard NodeSets do ("HasComponent", "Double").
  void write_aliases() {
    std::set<std::uint32_t> ids;
    for (const Node* node : nodes_) {
      for (const Reference& r : node->references) {
        if (r.reference_type_id.namespace_index == 0 && r.reference_type_id.is_numeric()) {
          ids.insert(r.reference_type_id.numeric());
        }
      }
      const NodeId* data_type = data_type_of(*node);
      if (data_type != nullptr && data_type->namespace_index == 0 && data_type->is_numeric()) {
        ids.insert(data_type->numeric());
      }
    }
    pugi::xml_node aliases = root_.append_child("Aliases");
    for (const std::uint32_t id : ids) {
      const Node* target = space_.find(NodeId(0, id));
      if (target == nullptr || target->browse_name.name.empty()) {
        continue;
      }
      const std::string alias = target->browse_name.name.str();
      pugi::xml_node e = aliases.append_child("Alias");
      e.append_attribute("Alias") = alias.c_str();
      e.text().set(fmt::format("i={}", id).c_str());
      alias_of_[id] = alias;
    }
  }

  static const NodeId* data_type_of(const Node& node) {
    if (const auto* variable = node.as<VariableNode>()) {
      return &variable->data_type;
    }
    if (const auto* variable_type = node.as<VariableTypeNode>()) {
      return &variable_type->data_type;
    }
    return nullptr;
  }

  std::string id_text(const NodeId& id) const {
    if (id.namespace_index == 0 && id.is_numeric()) {
      if (const auto it = alias_of_.find(id.numeric()); it != alias_of_.end()) {
        return it->second;
      }
    }
    return nodeset::XmlEncoder(map_).node_id(id);
  }

  // The source of the first inverse hierarchical reference other than HasSubtype.
  const NodeId* parent_of(const Node& node) const {
    for (const Reference& r : node.references) {
      if (!r.is_forward && r.reference_type_id != NodeId(0, id::HasSubtype) &&
          space_.is_hierarchical(r.reference_type_id)) {
        return &r.target_id;
      }
    }
    return nullptr;
  }

  void write_node(const Node& node) {
    pugi::xml_node e = root_.append_child(element_of(node.node_class()));
    const nodeset::XmlEncoder encoder(map_);
    e.append_attribute("NodeId") = encoder.node_id(node.node_id).c_str();
    e.append_attribute("BrowseName") = encoder.qualified_name(node.browse_name).c_str();
    if (const NodeId* parent = parent_of(node); parent != nullptr && !is_type(node.node_class())) {
      e.append_attribute("ParentNodeId") = id_text(*parent).c_str();
    }
    if (node.write_mask != 0) {
      e.append_attribute("WriteMask") = node.write_mask;
    }
    if (node.user_write_mask != 0) {
      e.append_attribute("UserWriteMask") = node.user_write_mask;
    }
    write_class_attributes(e, node);
    write_text(e, "DisplayName", node.display_name);
    write_text(e, "Description", node.description);
    if (const auto* reference_type = node.as<ReferenceTypeNode>()) {
      write_text(e, "InverseName", reference_type->inverse_name);
    }
    pugi::xml_node references = e.append_child("References");
    for (const Reference& r : sorted_references(node)) {
      pugi::xml_node ref = references.append_child("Reference");
      ref.append_attribute("ReferenceType") = id_text(r.reference_type_id).c_str();
      if (!r.is_forward) {
        ref.append_attribute("IsForward") = "false";
      }
      ref.text().set(id_text(r.target_id).c_str());
    }
    write_value(e, node);
  }

  // Stored order depends on the order of construction; files list them by type, direction and
  // target so that the same model always exports the same document.
  std::vector<Reference> sorted_references(const Node& node) const {
    std::vector<Reference> sorted = node.references;
    const auto key = [this](const Reference& r) {
      return std::make_tuple(id_text(r.reference_type_id), !r.is_forward, to_string(r.target_id));
    };
    std::sort(sorted.begin(), sorted.end(),
              [&key](const Reference& a, const Reference& b) { return key(a) < key(b); });
    return sorted;
  }

  static void write_text(pugi::xml_node e, const char* name, const LocalizedText& text) {
    if (text.text.is_null() || text.text.empty()) {
      return;
    }
    pugi::xml_node child = e.append_child(name);
    if (!text.locale.is_null() && !text.locale.empty()) {
      child.append_attribute("Locale") = text.locale.str().c_str();
    }
    child.text().set(text.text.str().c_str());
  }

  void write_class_attributes(pugi::xml_node e, const Node& node) const {
    if (const auto* object = node.as<ObjectNode>(); object != nullptr && object->event_notifier != 0) {
      e.append_attribute("EventNotifier") = object->event_notifier;
    } else if (const auto* variable = node.as<VariableNode>()) {
      write_value_attributes(e, *variable);
      e.append_attribute("AccessLevel") = variable->access_level;
      e.append_attribute("UserAccessLevel") = variable->user_access_level;
      if (variable->minimum_sampling_interval != 0.0) {
        e.append_attribute("MinimumSamplingInterval") = variable->minimum_sampling_interval;
      }
      if (variable->historizing) {
        e.append_attribute("Historizing") = "true";
      }
    } else if (const auto* method = node.as<MethodNode>(); method != nullptr && !method->executable) {
      e.append_attribute("Executable") = "false";
    } else if (const auto* variable_type = node.as<VariableTypeNode>()) {
      write_value_attributes(e, *variable_type);
      write_abstract(e, variable_type->is_abstract);
    } else if (const auto* object_type = node.as<ObjectTypeNode>()) {
      write_abstract(e, object_type->is_abstract);
    } else if (const auto* reference_type = node.as<ReferenceTypeNode>()) {
      write_abstract(e, reference_type->is_abstract);
      if (reference_type->symmetric) {
        e.append_attribute("Symmetric") = "true";
      }
    } else if (const auto* data_type = node.as<DataTypeNode>()) {
      write_abstract(e, data_type->is_abstract);
    } else if (const auto* view = node.as<ViewNode>()) {
      e.append_attribute("ContainsNoLoops") = view->contains_no_loops ? "true" : "false";
      if (view->event_notifier != 0) {
        e.append_attribute("EventNotifier") = view->event_notifier;
      }
    }
  }

  static void write_abstract(pugi::xml_node e, bool is_abstract) {
    if (is_abstract) {
      e.append_attribute("IsAbstract") = "true";
    }
  }

  template <typename N>
  void write_value_attributes(pugi::xml_node e, const N& node) const {
    e.append_attribute("DataType") = id_text(node.data_type).c_str();
    if (node.value_rank != value_rank::Scalar) {
      e.append_attribute("ValueRank") = node.value_rank;
    }
    if (!node.array_dimensions.empty()) {
      std::string dims;
      for (const std::uint32_t d : node.array_dimensions) {
        dims += (dims.empty() ? "" : ",") + std::to_string(d);
      }
      e.append_attribute("ArrayDimensions") = dims.c_str();
    }
  }

  void write_value(pugi::xml_node e, const Node& node) const {
    const Variant* value = nullptr;
    DataValue current;
    if (const auto* variable = node.as<VariableNode>()) {
      current = current_value(*variable);
      value = &current.value;
    } else if (const auto* variable_type = node.as<VariableTypeNode>()) {
      value = &variable_type->value.value;
    }
    if (value != nullptr && !value->is_empty()) {
      nodeset::XmlEncoder(map_).value(e.append_child("Value"), *value);
    }
  }

  const AddressSpace& space_;
  const NodeSetExportOptions& options_;
  std::set<std::uint16_t> exported_;
  std::vector<const Node*> nodes_;
  std::vector<std::string> file_namespaces_;
  nodeset::NamespaceMap map_;
  std::map<std::uint32_t, std::string> alias_of_;
  pugi::xml_document document_;
  pugi::xml_node root_;
};

}  // namespace

Result<std::string> export_nodeset(const AddressSpace& space, const NodeSetExportOptions& options) {
  return Exporter(space, options).run();
}

}  // namespace sf::opcua::server
