// Turning subscribe rules into Variables by browsing (see model_walk.hpp).
#include "model_walk.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <optional>
#include <unordered_set>

#include "sf/opcua/status_codes.hpp"

namespace sf::cloud::detail {

namespace {

namespace ua = sf::opcua;

// Requests are split so that a server with small operation limits still answers.
constexpr std::size_t kChunk = 500;
// A model with loops or millions of nodes stops the walk instead of the gateway.
constexpr std::size_t kBrowseBudget = 200'000;

// "2:Name" → (2, "Name"); "Name" → (nullopt, "Name").
std::pair<std::optional<std::uint16_t>, std::string_view> split_segment(std::string_view segment) {
  const auto colon = segment.find(':');
  std::uint16_t index = 0;
  if (colon != std::string_view::npos) {
    const auto [ptr, ec] = std::from_chars(segment.data(), segment.data() + colon, index);
    if (ec == std::errc{} && ptr == segment.data() + colon) {
      return {index, segment.substr(colon + 1)};
    }
  }
  return {std::nullopt, segment};
}

}  // namespace

Result<std::pair<ua::NodeId, ua::NodeClass>> resolve_browse_path(
    ua::SyncClient& client, std::string_view path,
    const std::function<Result<std::vector<ua::ReferenceDescription>>(const ua::NodeId&)>& browse) {
  ua::NodeId node(0, ua::id::RootFolder);
  ua::NodeClass node_class = ua::NodeClass::Object;
  std::size_t start = 1;
  while (start < path.size()) {
    const auto end = std::min(path.find('/', start), path.size());
    // Named, not a structured binding: the lambda below uses them.
    const auto segment = split_segment(path.substr(start, end - start));
    const std::optional<std::uint16_t> index = segment.first;
    const std::string_view name = segment.second;
    start = end + 1;
    if (name.empty()) {
      continue;
    }
    auto refs = browse ? browse(node) : client.browse_children(node);
    if (!refs) {
      return refs.error();
    }
    const auto found = std::find_if(refs->begin(), refs->end(), [&](const ua::ReferenceDescription& r) {
      return r.browse_name.name == name && (!index || r.browse_name.namespace_index == *index);
    });
    if (found == refs->end()) {
      return make_error(Errc::not_found,
                        fmt::format("browse path '{}': no '{}' below {}", path, name, ua::to_string(node)));
    }
    node = found->node_id.node_id;
    node_class = found->node_class;
  }
  return std::pair(node, node_class);
}

namespace {

class Walker {
 public:
  Walker(ua::SyncClient& client, const NamespaceTable& namespaces) : client_(client), ns_(namespaces) {}

  Status rule(const SubscribeRule& rule) {
    const std::size_t before = out_.variables.size();
    const std::size_t warned = out_.warnings.size();
    if (!rule.browse_path.empty()) {
      auto node = resolve_path(rule.browse_path);
      if (!node) {
        return node.error();
      }
      if (*node) {
        SF_TRY(collect((*node)->first, rule.browse_path, (*node)->second, rule.depth));
      }
    } else if (!rule.node.empty()) {
      SF_TRY(by_node(rule.node, rule.depth));
    } else {
      SF_TRY(instances_of(rule.type, rule.depth));
    }
    if (out_.variables.size() == before && out_.warnings.size() == warned) {
      out_.warnings.push_back(fmt::format(
          "subscribe rule '{}' matched no variable",
          !rule.browse_path.empty() ? rule.browse_path : (rule.node.empty() ? rule.type : rule.node)));
    }
    return describe(before);
  }

  Discovery take() { return std::move(out_); }

 private:
  Result<std::vector<ua::ReferenceDescription>> children(const ua::NodeId& node) {
    if (browsed_++ > kBrowseBudget) {
      return make_error(Errc::limit_exceeded, fmt::format("browsed more than {} nodes", kBrowseBudget));
    }
    return client_.browse_children(node);
  }

  // The node a browse path names, from the Root; nullopt (and a warning) when a name is missing.
  Result<std::optional<std::pair<ua::NodeId, ua::NodeClass>>> resolve_path(std::string_view path) {
    auto found =
        resolve_browse_path(client_, path, [this](const ua::NodeId& node) { return children(node); });
    if (!found && found.error().code == Errc::not_found) {
      out_.warnings.push_back(found.error().message);
      return std::optional<std::pair<ua::NodeId, ua::NodeClass>>{};
    }
    if (!found) {
      return found.error();
    }
    return std::optional(*found);
  }

  Status by_node(const std::string& text, unsigned depth) {
    auto node = ns_.parse(text);
    if (!node) {
      out_.warnings.push_back(fmt::format("node '{}': {}", text, node.error().message));
      return {};
    }
    auto attributes = client_.read({ua::ReadValueId{*node, ua::attribute_id::NodeClass, {}, {}},
                                    ua::ReadValueId{*node, ua::attribute_id::BrowseName, {}, {}}});
    if (!attributes) {
      return attributes.error();
    }
    const auto* node_class = (*attributes)[0].value.get_if<std::int32_t>();
    const auto* name = (*attributes)[1].value.get_if<ua::QualifiedName>();
    if (node_class == nullptr || name == nullptr) {
      out_.warnings.push_back(fmt::format("node '{}': {}", text, ua::to_string((*attributes)[0].status)));
      return {};
    }
    return collect(*node, "/" + name->name.str(), static_cast<ua::NodeClass>(*node_class), depth);
  }

  // Adds node when it is a Variable, then the Variables up to `depth` levels below it
  // (properties are descriptions, not data: HasProperty is not followed).
  Status collect(const ua::NodeId& node, const std::string& path, ua::NodeClass node_class, unsigned depth) {
    if (node_class == ua::NodeClass::Variable && seen_.insert(node).second) {
      out_.variables.push_back({node, ns_.stable_text(node), path, {}, {}});
    }
    if (depth == 0 || (node_class != ua::NodeClass::Object && node_class != ua::NodeClass::Variable)) {
      return {};
    }
    auto refs = children(node);
    if (!refs) {
      return refs.error();
    }
    for (const auto& r : *refs) {
      if (r.reference_type_id == ua::NodeId(0, ua::id::HasProperty) || !r.node_id.is_local()) {
        continue;
      }
      SF_TRY(collect(r.node_id.node_id, path + "/" + r.browse_name.name.str(), r.node_class, depth - 1));
    }
    return {};
  }

  // The type and its subtypes (forward HasSubtype, OPC 10000-3 §7.10).
  Status subtypes(const ua::NodeId& type, std::unordered_set<ua::NodeId>& types) {
    if (!types.insert(type).second) {
      return {};
    }
    ua::BrowseDescription d = ua::browse_children_of(type);
    d.reference_type_id = ua::NodeId(0, ua::id::HasSubtype);
    d.include_subtypes = false;
    auto refs = client_.browse(d);
    if (!refs) {
      return refs.error();
    }
    for (const auto& r : *refs) {
      SF_TRY(subtypes(r.node_id.node_id, types));
    }
    return {};
  }

  Status instances_of(const std::string& text, unsigned depth) {
    auto type = ns_.parse(text);
    if (!type) {
      out_.warnings.push_back(fmt::format("type '{}': {}", text, type.error().message));
      return {};
    }
    std::unordered_set<ua::NodeId> types;
    SF_TRY(subtypes(*type, types));
    return find_instances(ua::NodeId(0, ua::id::ObjectsFolder), "/Objects", types, depth, 8);
  }

  Status find_instances(const ua::NodeId& node, const std::string& path,
                        const std::unordered_set<ua::NodeId>& types, unsigned depth, unsigned levels) {
    auto refs = children(node);
    if (!refs) {
      return refs.error();
    }
    for (const auto& r : *refs) {
      if (r.node_class != ua::NodeClass::Object || !r.node_id.is_local() ||
          !visited_objects_.insert(r.node_id.node_id).second) {
        continue;
      }
      const std::string child = path + "/" + r.browse_name.name.str();
      if (types.contains(r.type_definition.node_id)) {
        SF_TRY(collect(r.node_id.node_id, child, r.node_class, depth));
      }
      if (levels > 1) {
        SF_TRY(find_instances(r.node_id.node_id, child, types, depth, levels - 1));
      }
    }
    return {};
  }

  // DataType and EngineeringUnits of the variables from `first` on.
  Status describe(std::size_t first) {
    for (std::size_t at = first; at < out_.variables.size(); at += kChunk) {
      const std::size_t end = std::min(out_.variables.size(), at + kChunk);
      std::vector<ua::ReadValueId> reads;
      std::vector<ua::BrowsePath> paths;
      for (std::size_t i = at; i < end; ++i) {
        reads.push_back({out_.variables[i].node, ua::attribute_id::DataType, {}, {}});
        ua::RelativePathElement units;
        units.reference_type_id = ua::NodeId(0, ua::id::HasProperty);
        units.target_name = ua::QualifiedName(0, "EngineeringUnits");
        ua::BrowsePath path;
        path.starting_node = out_.variables[i].node;
        path.relative_path.elements = ua::Array<ua::RelativePathElement>{units};
        paths.push_back(std::move(path));
      }
      auto types = client_.read(std::move(reads));
      if (!types) {
        return types.error();
      }
      for (std::size_t i = at; i < end; ++i) {
        if (const auto* id = (*types)[i - at].value.get_if<ua::NodeId>()) {
          out_.variables[i].data_type = *id;
        }
      }
      SF_TRY(units(at, std::move(paths)));
    }
    return {};
  }

  Status units(std::size_t at, std::vector<ua::BrowsePath> paths) {
    auto found = client_.translate(std::move(paths));
    if (!found) {
      return {};  // TranslateBrowsePaths is optional for what we need: no units then
    }
    std::vector<ua::ReadValueId> reads;
    std::vector<std::size_t> owners;
    for (std::size_t i = 0; i < found->size(); ++i) {
      const auto& result = (*found)[i];
      if (result.status_code.is_good() && !result.targets.empty()) {
        reads.push_back(ua::value_of(result.targets[0].target_id.node_id));
        owners.push_back(at + i);
      }
    }
    if (reads.empty()) {
      return {};
    }
    auto values = client_.read(std::move(reads));
    if (!values) {
      return values.error();
    }
    for (std::size_t i = 0; i < owners.size(); ++i) {
      if (const auto* eo = (*values)[i].value.get_if<ua::ExtensionObject>()) {
        if (const auto* eu = eo->get_if<ua::EUInformation>()) {
          out_.variables[owners[i]].unit = eu->display_name.text.str();
        }
      }
    }
    return {};
  }

  ua::SyncClient& client_;
  const NamespaceTable& ns_;
  Discovery out_;
  std::unordered_set<ua::NodeId> seen_;
  std::unordered_set<ua::NodeId> visited_objects_;
  std::size_t browsed_ = 0;
};

}  // namespace

Result<NamespaceTable> NamespaceTable::read(ua::SyncClient& client) {
  auto value = client.read_value(ua::NodeId(0, ua::id::Server_NamespaceArray));
  if (!value) {
    return value.error();
  }
  const auto* names = value->value.array_if<ua::String>();
  if (names == nullptr) {
    return ua::status_error(ua::status::BadTypeMismatch, "the server's NamespaceArray is not a String array");
  }
  std::vector<std::string> uris;
  for (const auto& name : *names) {
    uris.push_back(name.str());
  }
  return NamespaceTable(std::move(uris));
}

Result<ua::NodeId> NamespaceTable::parse(std::string_view text) const {
  std::optional<std::uint16_t> index;
  if (text.starts_with("nsu=")) {
    const auto semi = text.find(';');
    if (semi == std::string_view::npos) {
      return make_error(Errc::invalid_argument,
                        fmt::format("'{}': nsu=URI must be followed by ;i=, ;s=, ...", text));
    }
    const std::string_view uri = text.substr(4, semi - 4);
    for (std::size_t i = 0; i < uris_.size(); ++i) {
      if (uris_[i] == uri) {
        index = static_cast<std::uint16_t>(i);
      }
    }
    if (!index) {
      return make_error(Errc::not_found, fmt::format("the server has no namespace '{}'", uri));
    }
    text = text.substr(semi + 1);
  }
  auto id = ua::NodeId::parse(text);
  if (!id) {
    return id.error();
  }
  if (index) {
    id->namespace_index = *index;
  }
  return id;
}

std::string NamespaceTable::stable_text(const ua::NodeId& id) const {
  if (id.namespace_index == 0 || id.namespace_index >= uris_.size()) {
    return ua::to_string(id);
  }
  ua::NodeId local = id;
  local.namespace_index = 0;
  return fmt::format("nsu={};{}", uris_[id.namespace_index], ua::to_string(local));
}

Result<Discovery> discover(ua::SyncClient& client, const NamespaceTable& namespaces,
                           const std::vector<SubscribeRule>& rules) {
  Walker walker(client, namespaces);
  for (const SubscribeRule& rule : rules) {
    SF_TRY(walker.rule(rule));
  }
  return walker.take();
}

}  // namespace sf::cloud::detail
