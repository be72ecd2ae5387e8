// NodeSet2 import (OPC 10000-6 Annex F): parse and check the whole document, then apply it.
#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "sf/core/log.hpp"
#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/status_codes.hpp"
#include "xml_codec.hpp"

namespace sf::opcua::server {

namespace {

using nodeset::child_element;
using nodeset::local_name;

struct ParsedReference {
  NodeId type;
  NodeId target;
  bool forward = true;
  pugi::xml_node at;
};

struct ParsedNode {
  NodeId id;
  std::unique_ptr<Node> node;
  std::vector<ParsedReference> references;
  pugi::xml_node at;
};

// The element name of each NodeClass (OPC 10000-6 §F.3).
NodeClass node_class_of(std::string_view element) {
  static const std::pair<std::string_view, NodeClass> kClasses[] = {
      {"UAObject", NodeClass::Object},
      {"UAVariable", NodeClass::Variable},
      {"UAMethod", NodeClass::Method},
      {"UAObjectType", NodeClass::ObjectType},
      {"UAVariableType", NodeClass::VariableType},
      {"UAReferenceType", NodeClass::ReferenceType},
      {"UADataType", NodeClass::DataType},
      {"UAView", NodeClass::View},
  };
  for (const auto& [name, node_class] : kClasses) {
    if (name == element) {
      return node_class;
    }
  }
  return NodeClass::Unspecified;
}

// Byte offsets → "name:line:column" for error messages.
class SourceLines {
 public:
  SourceLines(std::string_view text, std::string name) : name_(std::move(name)) {
    for (std::size_t i = 0; i < text.size(); ++i) {
      if (text[i] == '\n') {
        line_starts_.push_back(i + 1);
      }
    }
  }
  [[nodiscard]] std::string where(std::ptrdiff_t offset) const {
    if (offset < 0) {
      return name_;
    }
    const auto at = static_cast<std::size_t>(offset);
    const auto next = std::upper_bound(line_starts_.begin(), line_starts_.end(), at);
    const auto line = static_cast<std::size_t>(next - line_starts_.begin());
    return fmt::format("{}:{}:{}", name_, line, at - line_starts_[line - 1] + 1);
  }
  // pugixml's offset of an element is that of its name, one past the '<'.
  [[nodiscard]] std::string where(pugi::xml_node node) const {
    const std::ptrdiff_t offset = node.offset_debug();
    return where(node.type() == pugi::node_element && offset > 0 ? offset - 1 : offset);
  }

 private:
  std::string name_;
  std::vector<std::size_t> line_starts_{0};
};

class Importer {
 public:
  Importer(AddressSpace& space, std::string_view xml, const NodeSetImportOptions& options)
      : space_(space),
        xml_(xml),
        options_(options),
        lines_(xml, options.source_name),
        decoder_(namespaces_, [this](pugi::xml_node n) { return lines_.where(n); }) {}

  Result<NodeSetImportReport> run() {
    SF_TRY(parse());
    SF_TRY(check_ids());
    for (const auto& uri : report_.namespace_uris) {
      space_.add_namespace(uri);
    }
    SF_TRY(add_nodes());
    add_references();
    return std::move(report_);
  }

 private:
  Error error_at(pugi::xml_node at, std::string_view message) const {
    return make_error(Errc::malformed, fmt::format("{}: {}", lines_.where(at), message));
  }

  Status parse() {
    const pugi::xml_parse_result parsed =
        document_.load_buffer(xml_.data(), xml_.size(), pugi::parse_default);
    if (!parsed) {
      return make_error(Errc::malformed, fmt::format("{}: not well-formed XML: {}",
                                                     lines_.where(parsed.offset), parsed.description()));
    }
    const pugi::xml_node root = document_.document_element();
    if (local_name(root) != "UANodeSet") {
      return error_at(root, fmt::format("the root element is <{}>, not <UANodeSet>", root.name()));
    }
    SF_TRY(read_namespaces(root));
    SF_TRY(read_aliases(root));
    for (pugi::xml_node e = root.first_child(); e; e = e.next_sibling()) {
      const NodeClass node_class = node_class_of(local_name(e));
      if (e.type() != pugi::node_element || node_class == NodeClass::Unspecified) {
        continue;  // NamespaceUris, Models, Aliases, Extensions ...
      }
      auto node = read_node(e, node_class);
      if (!node) {
        return node.error();
      }
      nodes_.push_back(std::move(*node));
    }
    return {};
  }

  // The file's namespace i is the server's namespace to[i]: existing URIs keep their index, new
  // ones are appended in file order (run() registers them in that order).
  Status read_namespaces(pugi::xml_node root) {
    std::vector<std::uint16_t> to{0};
    std::size_t next = space_.namespaces().size();
    for (pugi::xml_node uri = child_element(root, "NamespaceUris").first_child(); uri;
         uri = uri.next_sibling()) {
      if (uri.type() != pugi::node_element) {
        continue;
      }
      const std::string text = uri.child_value();
      if (text.empty()) {
        return error_at(uri, "empty namespace URI");
      }
      const auto existing = space_.namespace_index(text);
      const std::size_t index = existing ? *existing : next++;
      if (index > 0xFFFF) {
        return error_at(uri, "too many namespaces");
      }
      to.push_back(static_cast<std::uint16_t>(index));
      report_.namespace_uris.push_back(text);
    }
    namespaces_ = nodeset::NamespaceMap(std::move(to));
    return {};
  }

  Status read_aliases(pugi::xml_node root) {
    for (pugi::xml_node alias = child_element(root, "Aliases").first_child(); alias;
         alias = alias.next_sibling()) {
      if (alias.type() != pugi::node_element) {
        continue;
      }
      auto id = decoder_.node_id(alias, alias.child_value());
      if (!id) {
        return id.error();
      }
      aliases_[alias.attribute("Alias").value()] = std::move(*id);
    }
    return {};
  }

  // An alias (OPC 10000-6 §F.4) or a NodeId in text form.
  Result<NodeId> resolve(pugi::xml_node at, std::string_view text) {
    if (const auto it = aliases_.find(std::string(text)); it != aliases_.end()) {
      return it->second;
    }
    if (text.find('=') == std::string_view::npos) {
      return error_at(at, fmt::format("'{}' is neither an alias of <Aliases> nor a NodeId", text));
    }
    return decoder_.node_id(at, text);
  }

  template <typename T>
  Status number(pugi::xml_node e, const char* name, T& out) {
    const pugi::xml_attribute a = e.attribute(name);
    if (!a) {
      return {};
    }
    const std::string_view text = a.value();
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    if (ec != std::errc{} || ptr != text.data() + text.size()) {
      return error_at(e, fmt::format("{}=\"{}\" is not a valid number", name, text));
    }
    return {};
  }

  static bool flag(pugi::xml_node e, const char* name, bool fallback) {
    return e.attribute(name).as_bool(fallback);
  }

  static LocalizedText localized(pugi::xml_node e) {
    if (!e) {
      return {};
    }
    const pugi::xml_attribute locale = e.attribute("Locale");
    return LocalizedText(locale ? String(locale.value()) : String(), String(e.child_value()));
  }

  Result<ParsedNode> read_node(pugi::xml_node e, NodeClass node_class) {
    ParsedNode parsed;
    parsed.at = e;
    parsed.node = make_node(node_class);
    Node& node = *parsed.node;
    auto id = decoder_.node_id(e, e.attribute("NodeId").value());
    if (!id) {
      return id.error();
    }
    node.node_id = *id;
    parsed.id = std::move(*id);
    auto browse_name = decoder_.qualified_name(e, e.attribute("BrowseName").value());
    if (!browse_name) {
      return browse_name.error();
    }
    node.browse_name = std::move(*browse_name);
    node.display_name = localized(child_element(e, "DisplayName"));
    if (node.display_name.text.empty()) {
      node.display_name = LocalizedText(String(), node.browse_name.name);
    }
    node.description = localized(child_element(e, "Description"));
    SF_TRY(number(e, "WriteMask", node.write_mask));
    SF_TRY(number(e, "UserWriteMask", node.user_write_mask));
    SF_TRY(read_class_attributes(e, node));
    SF_TRY(read_references(e, parsed));
    return parsed;
  }

  Status read_class_attributes(pugi::xml_node e, Node& node) {
    if (auto* object = node.as<ObjectNode>()) {
      return number(e, "EventNotifier", object->event_notifier);
    }
    if (auto* variable = node.as<VariableNode>()) {
      return read_variable(e, *variable);
    }
    if (auto* method = node.as<MethodNode>()) {
      method->executable = flag(e, "Executable", true);
      method->user_executable = flag(e, "UserExecutable", true);
    } else if (auto* object_type = node.as<ObjectTypeNode>()) {
      object_type->is_abstract = flag(e, "IsAbstract", false);
    } else if (auto* variable_type = node.as<VariableTypeNode>()) {
      return read_variable_type(e, *variable_type);
    } else if (auto* reference_type = node.as<ReferenceTypeNode>()) {
      reference_type->is_abstract = flag(e, "IsAbstract", false);
      reference_type->symmetric = flag(e, "Symmetric", false);
      reference_type->inverse_name = localized(child_element(e, "InverseName"));
    } else if (auto* data_type = node.as<DataTypeNode>()) {
      data_type->is_abstract = flag(e, "IsAbstract", false);
    } else if (auto* view = node.as<ViewNode>()) {
      view->contains_no_loops = flag(e, "ContainsNoLoops", false);
      return number(e, "EventNotifier", view->event_notifier);
    }
    return {};
  }

  // The attributes Variables and VariableTypes share (UANodeSet.xsd defaults: DataType i=24,
  // ValueRank -1).
  template <typename N>
  Status read_value_attributes(pugi::xml_node e, N& node) {
    if (const pugi::xml_attribute data_type = e.attribute("DataType")) {
      auto id = resolve(e, data_type.value());
      if (!id) {
        return id.error();
      }
      node.data_type = std::move(*id);
    }
    node.value_rank = value_rank::Scalar;
    SF_TRY(number(e, "ValueRank", node.value_rank));
    SF_TRY(read_array_dimensions(e, node.array_dimensions));
    if (const pugi::xml_node value = child_element(e, "Value")) {
      auto decoded = decoder_.value(value);
      if (!decoded) {
        return decoded.error();
      }
      node.value = DataValue(std::move(*decoded));
    }
    return {};
  }

  Status read_variable(pugi::xml_node e, VariableNode& variable) {
    SF_TRY(read_value_attributes(e, variable));
    variable.access_level = access_level::CurrentRead;
    variable.user_access_level = access_level::CurrentRead;
    variable.minimum_sampling_interval = 0.0;
    SF_TRY(number(e, "AccessLevel", variable.access_level));
    SF_TRY(number(e, "UserAccessLevel", variable.user_access_level));
    SF_TRY(number(e, "MinimumSamplingInterval", variable.minimum_sampling_interval));
    variable.historizing = flag(e, "Historizing", false);
    return {};
  }

  Status read_variable_type(pugi::xml_node e, VariableTypeNode& variable_type) {
    SF_TRY(read_value_attributes(e, variable_type));
    variable_type.is_abstract = flag(e, "IsAbstract", false);
    return {};
  }

  // "2,3" (OPC 10000-6 §F.3: ArrayDimensions as a comma-separated list).
  Status read_array_dimensions(pugi::xml_node e, std::vector<std::uint32_t>& out) {
    std::string_view text = e.attribute("ArrayDimensions").value();
    out.clear();
    while (!text.empty()) {
      const auto comma = text.find(',');
      const std::string_view part = text.substr(0, comma);
      std::uint32_t length = 0;
      const auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), length);
      if (ec != std::errc{} || ptr != part.data() + part.size()) {
        return error_at(e, fmt::format("ArrayDimensions=\"{}\" is not a list of lengths",
                                       e.attribute("ArrayDimensions").value()));
      }
      out.push_back(length);
      text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
    }
    return {};
  }

  Status read_references(pugi::xml_node e, ParsedNode& parsed) {
    for (pugi::xml_node r = child_element(e, "References").first_child(); r; r = r.next_sibling()) {
      if (r.type() != pugi::node_element) {
        continue;
      }
      auto type = resolve(r, r.attribute("ReferenceType").value());
      if (!type) {
        return type.error();
      }
      auto target = resolve(r, r.child_value());
      if (!target) {
        return target.error();
      }
      parsed.references.push_back({std::move(*type), std::move(*target), flag(r, "IsForward", true), r});
    }
    return {};
  }

  Status check_ids() {
    std::unordered_set<NodeId> seen;
    for (const ParsedNode& parsed : nodes_) {
      const NodeId& id = parsed.id;
      if (!seen.insert(id).second) {
        return error_at(parsed.at, fmt::format("NodeId {} appears twice", to_string(id)));
      }
      const bool existing = space_.contains(id);
      if (existing && !(id.namespace_index == 0 && options_.skip_existing_namespace0)) {
        return make_error(Errc::invalid_argument,
                          fmt::format("{}: BadNodeIdExists: the address space already has {}",
                                      lines_.where(parsed.at), to_string(id)));
      }
    }
    return {};
  }

  // All nodes or none: a failure removes the nodes added before it.
  Status add_nodes() {
    std::vector<NodeId> added;
    for (ParsedNode& parsed : nodes_) {
      if (space_.contains(parsed.id)) {
        ++report_.nodes_skipped;
        continue;
      }
      auto result = space_.add_node(std::move(parsed.node));
      if (!result) {
        for (const NodeId& undo : added) {
          (void)space_.delete_node(undo);
        }
        return result.error().with_context(lines_.where(parsed.at));
      }
      added.push_back(parsed.id);
    }
    report_.nodes_added = added.size();
    return {};
  }

  void add_references() {
    for (const ParsedNode& parsed : nodes_) {
      const NodeId& source = parsed.id;
      for (const ParsedReference& r : parsed.references) {
        const Status added = space_.add_reference(source, r.type, r.target, r.forward);
        if (added) {
          ++report_.references_added;
        } else if (status_of(added.error()) != StatusCode(status::BadDuplicateReferenceNotAllowed)) {
          // Files list most references on both ends; the second one is a duplicate.
          report_.warnings.push_back(fmt::format("{}: reference {} {} {} skipped: {}", lines_.where(r.at),
                                                 to_string(r.type), r.forward ? "to" : "from",
                                                 to_string(r.target), added.error().message));
        }
      }
    }
  }

  AddressSpace& space_;
  std::string_view xml_;
  const NodeSetImportOptions& options_;
  SourceLines lines_;
  nodeset::NamespaceMap namespaces_;
  nodeset::XmlDecoder decoder_;
  pugi::xml_document document_;
  std::unordered_map<std::string, NodeId> aliases_;
  std::vector<ParsedNode> nodes_;
  NodeSetImportReport report_;
};

}  // namespace

Result<NodeSetImportReport> import_nodeset(AddressSpace& space, std::string_view xml,
                                           const NodeSetImportOptions& options) {
  auto report = Importer(space, xml, options).run();
  if (report) {
    log::get("opcua")->debug("{}: imported {} nodes ({} existing skipped), {} references, {} warnings",
                             options.source_name, report->nodes_added, report->nodes_skipped,
                             report->references_added, report->warnings.size());
  }
  return report;
}

Result<NodeSetImportReport> import_nodeset_file(AddressSpace& space, const std::filesystem::path& path,
                                                NodeSetImportOptions options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return make_error(Errc::io, fmt::format("{}: cannot open the NodeSet2 file", path.string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (options.source_name == NodeSetImportOptions{}.source_name) {
    options.source_name = path.string();
  }
  return import_nodeset(space, text.str(), options);
}

Result<std::vector<NodeSetImportReport>> import_nodeset_files(AddressSpace& space,
                                                              const std::vector<std::string>& files) {
  std::vector<NodeSetImportReport> reports;
  for (const std::string& file : files) {
    auto report = import_nodeset_file(space, file);
    if (!report) {
      return report.error();
    }
    reports.push_back(std::move(*report));
  }
  return reports;
}

}  // namespace sf::opcua::server
