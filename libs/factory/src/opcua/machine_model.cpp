// MachineModel (machine_model.hpp): the nodes of one machine, built from the layout tables, and
// the values the controller's thread publishes written into them.
#include "sf/factory/machine_model.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "opcua/model_layout.hpp"
#include "opcua/model_nodes.hpp"
#include "sf/core/log.hpp"
#include "sf/line/ontology.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/opcua/units.hpp"

namespace sf::factory {

namespace ua = sf::opcua;
namespace srv = sf::opcua::server;
using ua::NodeId;
using ua::QualifiedName;

namespace {

std::string_view parent_path(std::string_view path) {
  const auto dot = path.rfind('.');
  return dot == std::string_view::npos ? std::string_view{} : path.substr(0, dot);
}

std::string_view leaf(std::string_view path) {
  const auto dot = path.rfind('.');
  return dot == std::string_view::npos ? path : path.substr(dot + 1);
}

// The node of `node_class` in namespace `ns` with this browse name, or nullptr.
const srv::Node* find_named(const srv::AddressSpace& space, std::uint16_t ns, std::string_view name,
                            ua::NodeClass node_class) {
  const srv::Node* found = nullptr;
  space.for_each_node([&](const srv::Node& n) {
    if (found == nullptr && n.node_class() == node_class && n.browse_name.namespace_index == ns &&
        n.browse_name.name == name) {
      found = &n;
    }
  });
  return found;
}

// The ontology class a machine of `kind` belongs to (ontology/candy-factory.ttl).
std::string_view class_of_kind(std::string_view kind) {
  if (kind == "conveyor") {
    return "Conveyor";
  }
  if (kind == "uploader") {
    return "BoxUploader";
  }
  if (kind == "downloader") {
    return "BoxDownloader";
  }
  return kind.ends_with("robot") ? "Robot" : "Machine";
}

NodeId machines_folder(std::uint16_t ns) {
  return NodeId(ns, ua::String("Machines"));
}

// Once per address space: the stand-in ObjectTypes and the Machines folder (OPC 40001-1 §10).
Status ensure_shared_nodes(srv::AddressSpace& space, std::uint16_t ns) {
  for (const auto& row : model::kObjects) {
    const NodeId type(ns, ua::String(row.type));
    if (row.type.empty() || space.contains(type)) {
      continue;
    }
    srv::ObjectTypeSpec spec;
    spec.node_id = type;
    spec.browse_name = QualifiedName(ns, ua::String(row.type));
    spec.parent = ns0(ua::id::BaseObjectType);
    SF_TRY(space.add_object_type(spec));
  }
  if (space.contains(machines_folder(ns))) {
    return {};
  }
  srv::ObjectSpec folder;
  folder.node_id = machines_folder(ns);
  folder.browse_name = QualifiedName(ns, "Machines");
  folder.description = {ua::String(), "The machines this server shows (OPC 40001-1 §10)"};
  folder.parent = ns0(ua::id::ObjectsFolder);
  folder.reference_type = ns0(ua::id::Organizes);
  folder.type_definition = ns0(ua::id::FolderType);
  return space.add_object(folder).ok() ? Status{} : make_error(Errc::state, "cannot add the Machines folder");
}

// The ontology's individual named `name`, linked into the Machines folder; else a new object
// typed by the ontology's class for the machine's kind (BaseObjectType without the ontology).
Result<NodeId> machine_object(srv::AddressSpace& space, std::uint16_t ns, const std::string& name,
                              const Identification& identification, const MachineModelOptions& options) {
  const auto onto =
      options.ontology_namespace.empty() ? std::nullopt : space.namespace_index(options.ontology_namespace);
  if (onto) {
    if (const srv::Node* individual = find_named(space, *onto, name, ua::NodeClass::Object)) {
      SF_TRY(space.add_reference(machines_folder(ns), ns0(ua::id::Organizes), individual->node_id));
      return individual->node_id;
    }
  }
  srv::ObjectSpec spec;
  spec.node_id = NodeId(ns, ua::String(name));
  spec.browse_name = QualifiedName(ns, ua::String(name));
  spec.description = {ua::String(),
                      ua::String(fmt::format("{} ({})", identification.name, identification.kind))};
  spec.parent = machines_folder(ns);
  spec.reference_type = ns0(ua::id::Organizes);
  const srv::Node* type =
      onto ? find_named(space, *onto, class_of_kind(identification.kind), ua::NodeClass::ObjectType)
           : nullptr;
  spec.type_definition = type != nullptr ? type->node_id : ns0(ua::id::BaseObjectType);
  spec.instantiate_mandatory = false;
  return space.add_object(spec);
}

// OPC 40001-1 §8.4 (MachineIdentificationType with the IMachineVendorNameplateType and
// IMachineTagNameplateType properties): recommended ProductInstanceUri is
// <ManufacturerUri>/<Model>/<SerialNumber>; without a ManufacturerUri a URN stands in.
std::vector<std::pair<std::string_view, ua::Variant>> identification_values(const Identification& id) {
  const auto text = [](const std::string& s) { return ua::Variant(ua::LocalizedText(ua::String(), s)); };
  return {{"Manufacturer", text(id.manufacturer)},
          {"Model", text(id.model)},
          {"SerialNumber", id.serial_number},
          {"ProductInstanceUri",
           fmt::format("urn:smartfactory:{}:{}:{}", id.manufacturer, id.model, id.serial_number)},
          {"DeviceClass", id.kind},
          {"ComponentName", text(id.name)}};
}

}  // namespace

NodeId MachineModel::node(std::string_view path) const {
  return path.empty() ? machine_ : NodeId(ns_, ua::String(fmt::format("{}.{}", name_, path)));
}

Result<MachineModel> MachineModel::create(srv::AddressSpace& space, const Identification& identification,
                                          const CommandHandler& commands,
                                          const MachineModelOptions& options) {
  const std::string name = line::iri_name(identification.name);
  if (name.empty()) {
    return make_error(Errc::invalid_argument,
                      fmt::format("machine name '{}' has no letters or digits", identification.name));
  }
  const std::uint16_t ns = space.add_namespace(options.namespace_uri);
  SF_TRY(ensure_shared_nodes(space, ns));
  auto machine = machine_object(space, ns, name, identification, options);
  if (!machine) {
    return machine.error().with_context(fmt::format("machine {}", name));
  }
  MachineModel m(ns, name, *machine);
  for (const auto& row : model::kObjects) {
    srv::ObjectSpec spec;
    spec.node_id = m.node(row.path);
    spec.browse_name = QualifiedName(ns, ua::String(leaf(row.path)));
    spec.parent = m.node(parent_path(row.path));
    spec.reference_type = ns0(row.reference);
    spec.type_definition = row.type.empty() ? ns0(ua::id::FolderType) : NodeId(ns, ua::String(row.type));
    spec.instantiate_mandatory = false;
    SF_TRY(space.add_object(spec));
  }
  for (const auto& [leaf_name, value] : identification_values(identification)) {
    const std::string path = fmt::format("Identification.{}", leaf_name);
    auto spec = variable_spec(m.node(path), QualifiedName(ns, ua::String(leaf_name)),
                              m.node("Identification"), static_cast<std::uint32_t>(value.type()), true);
    spec.value = value;
    SF_TRY(space.add_variable(spec));
  }
  for (const auto& row : model::kVariables) {
    auto spec = variable_spec(m.node(row.path), QualifiedName(ns, ua::String(leaf(row.path))),
                              m.node(parent_path(row.path)), row.data_type, false);
    if (row.array) {
      spec.value_rank = srv::value_rank::OneDimension;
      spec.array_dimensions = {kPackMLStates};
    }
    spec.value.status = ua::status::BadWaitingForInitialData;  // until the controller publishes
    historize(spec);
    SF_TRY(space.add_variable(spec));
  }
  for (const auto& row : model::kMethods) {
    srv::MethodSpec spec;
    const std::string_view method = to_string(row.command);
    spec.node_id = m.node(fmt::format("{}.{}", row.object, method));
    spec.browse_name = QualifiedName(ns, ua::String(method));
    spec.parent = m.node(row.object);
    spec.callback = [commands, command = row.command](const NodeId&, const std::vector<ua::Variant>&,
                                                      std::vector<ua::Variant>&) {
      return commands(command);
    };
    SF_TRY(space.add_method(spec));
  }
  return m;
}

Status MachineModel::add_tag(srv::AddressSpace& space, const ModelValue& value) {
  const std::string& tag = value.name;
  const std::string path = "Tags." + tag;
  auto spec = variable_spec(node(path), QualifiedName(ns_, ua::String(tag)), node("Tags"),
                            static_cast<std::uint32_t>(value.value.value.type()), false);
  spec.value = value.value;
  historize(spec);
  SF_TRY(space.add_variable(spec));
  auto reason =
      variable_spec(node(path + ".Reason"), QualifiedName(ns_, "Reason"), node(path), ua::id::String, true);
  reason.value = ua::Variant(std::string());
  SF_TRY(space.add_variable(reason));
  if (const auto eu = ua::unece_unit(value.unit)) {
    auto units = variable_spec(node(path + ".EngineeringUnits"), QualifiedName(0, "EngineeringUnits"),
                               node(path), ua::id::EUInformation, true);
    units.value = ua::Variant(ua::ExtensionObject::make(*eu));
    SF_TRY(space.add_variable(units));
  }
  tags_.emplace(tag, value.value.value.type());
  return {};
}

void MachineModel::remove_tag(srv::AddressSpace& space, const std::string& tag) {
  (void)space.delete_node(node(fmt::format("Tags.{}.EngineeringUnits", tag)));
  (void)space.delete_node(node(fmt::format("Tags.{}.Reason", tag)));
  (void)space.delete_node(node("Tags." + tag));
  tags_.erase(tag);
}

void MachineModel::apply(srv::AddressSpace& space, const std::vector<ModelValue>& values) {
  static const auto logger = log::get("factory");
  for (const ModelValue& v : values) {
    Status written;
    const auto tag = tags_.find(v.name);
    if (v.kind == ModelValue::Kind::fixed) {
      written = space.set_value(node(v.name), v.value);
    } else if (v.kind == ModelValue::Kind::tag_reason) {
      written = tag == tags_.end() ? Status{}
                                   : space.set_value(node(fmt::format("Tags.{}.Reason", v.name)), v.value);
    } else if (v.value.value.is_empty() && v.value.status == ua::status::BadNotFound) {
      remove_tag(space, v.name);
    } else if (tag == tags_.end()) {
      written = add_tag(space, v);
    } else {
      if (tag->second != v.value.value.type()) {  // the controller changed the tag's type
        if (auto* n = space.find_mutable_as<srv::VariableNode>(node("Tags." + v.name))) {
          n->data_type = ns0(static_cast<std::uint32_t>(v.value.value.type()));
        }
        tag->second = v.value.value.type();
      }
      written = space.set_value(node("Tags." + v.name), v.value);
    }
    if (!written) {
      logger->warn("machine {}: {}: {}", name_, v.name, written.error().message);
    }
  }
}

std::string method_object_path(PackMLCommand command) {
  for (const auto& row : model::kMethods) {
    if (row.command == command) {
      std::string path(row.object);
      std::replace(path.begin(), path.end(), '.', '/');
      return path;
    }
  }
  return {};
}

std::optional<PackMLCommand> packml_command(std::string_view name) {
  for (const auto& row : model::kMethods) {
    if (to_string(row.command) == name) {
      return row.command;
    }
  }
  return std::nullopt;
}

}  // namespace sf::factory
