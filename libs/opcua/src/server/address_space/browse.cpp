// The View service set (OPC 10000-4 §5.8): Browse, BrowseNext with continuation points (§7.9),
// TranslateBrowsePathsToNodeIds (§5.8.4), RegisterNodes and UnregisterNodes.
#include <algorithm>
#include <cstring>
#include <limits>

#include "server/address_space/service_util.hpp"

namespace sf::opcua::server {

namespace {

using detail::logger;

bool has(std::uint32_t mask, BrowseResultMask bit) {
  return (mask & static_cast<std::uint32_t>(bit)) != 0;
}

// The ReferenceDescription of one reference, with only the fields resultMask asks for
// (OPC 10000-4 §5.8.2.2: the others keep their null values).
ReferenceDescription describe(const AddressSpace& space, const Reference& r, const Node* target,
                              std::uint32_t result_mask) {
  ReferenceDescription d;
  d.node_id = ExpandedNodeId(r.target_id);
  if (has(result_mask, BrowseResultMask::ReferenceTypeId)) {
    d.reference_type_id = r.reference_type_id;
  }
  if (has(result_mask, BrowseResultMask::IsForward)) {
    d.is_forward = r.is_forward;
  }
  if (target == nullptr) {
    return d;
  }
  if (has(result_mask, BrowseResultMask::NodeClass)) {
    d.node_class = target->node_class();
  }
  if (has(result_mask, BrowseResultMask::BrowseName)) {
    d.browse_name = target->browse_name;
  }
  if (has(result_mask, BrowseResultMask::DisplayName)) {
    d.display_name = target->display_name;
  }
  const bool instance =
      target->node_class() == NodeClass::Object || target->node_class() == NodeClass::Variable;
  if (has(result_mask, BrowseResultMask::TypeDefinition) && instance) {
    if (const NodeId* type = space.type_definition(r.target_id)) {
      d.type_definition = ExpandedNodeId(*type);
    }
  }
  return d;
}

bool type_matches(const AddressSpace& space, const NodeId& actual, const NodeId& wanted,
                  bool include_subtypes) {
  return wanted.is_null() || actual == wanted || (include_subtypes && space.is_subtype(actual, wanted));
}

// The references a BrowseDescription selects, or a Bad status.
StatusCode collect(const AddressSpace& space, const BrowseDescription& d, const UserContext* user,
                   std::vector<ReferenceDescription>& out) {
  const Node* node = space.find(d.node_id);
  if (node == nullptr || (user != nullptr && !user->can_browse(*node))) {
    return status::BadNodeIdUnknown;
  }
  const auto direction = static_cast<std::int32_t>(d.browse_direction);
  if (direction < 0 || direction > static_cast<std::int32_t>(BrowseDirection::Both)) {
    return status::BadBrowseDirectionInvalid;
  }
  if (!d.reference_type_id.is_null() && space.find_as<ReferenceTypeNode>(d.reference_type_id) == nullptr) {
    return status::BadReferenceTypeIdInvalid;
  }
  for (const auto& r : node->references) {
    if ((d.browse_direction == BrowseDirection::Forward && !r.is_forward) ||
        (d.browse_direction == BrowseDirection::Inverse && r.is_forward) ||
        !type_matches(space, r.reference_type_id, d.reference_type_id, d.include_subtypes)) {
      continue;
    }
    const Node* target = space.find(r.target_id);
    if (d.node_class_mask != 0 &&
        (target == nullptr || (d.node_class_mask & static_cast<std::uint32_t>(target->node_class())) == 0)) {
      continue;
    }
    out.push_back(describe(space, r, target, d.result_mask));
  }
  return {};
}

// Returns up to `max` references now and parks the rest in a continuation point.
void page(std::vector<ReferenceDescription> all, std::uint32_t max, BrowseContinuations* continuations,
          BrowseResult& result) {
  if (max == 0 || all.size() <= max) {
    result.references = std::move(all);
    return;
  }
  BrowseContinuations::Pending pending;
  pending.max_references = max;
  pending.remaining.assign(std::make_move_iterator(all.begin() + max), std::make_move_iterator(all.end()));
  all.resize(max);
  auto point = continuations != nullptr ? continuations->add(std::move(pending)) : std::nullopt;
  if (!point) {
    // OPC 10000-4 §5.8.2.2: no continuation point left for this session.
    result.status_code = status::BadNoContinuationPoints;
    logger()->debug("Browse: no continuation point left");
    return;
  }
  result.references = std::move(all);
  result.continuation_point = std::move(*point);
}

std::uint32_t max_references(std::uint32_t requested, const OperationLimits& limits) {
  if (requested == 0) {
    return limits.max_references_per_node;
  }
  return limits.max_references_per_node == 0 ? requested
                                             : std::min(requested, limits.max_references_per_node);
}

}  // namespace

// ---- BrowseContinuations

std::optional<ByteString> BrowseContinuations::add(Pending pending) {
  if (points_.size() >= max_count_) {
    return std::nullopt;
  }
  Bytes id(sizeof(next_id_));
  std::memcpy(id.data(), &next_id_, sizeof(next_id_));
  ++next_id_;
  points_.emplace(id, std::move(pending));
  return ByteString(std::move(id));
}

std::optional<BrowseContinuations::Pending> BrowseContinuations::take(const ByteString& id) {
  auto it = points_.find(id.bytes());
  if (it == points_.end()) {
    return std::nullopt;
  }
  Pending pending = std::move(it->second);
  points_.erase(it);
  return pending;
}

bool BrowseContinuations::release(const ByteString& id) {
  return points_.erase(id.bytes()) > 0;
}

// ---- Browse / BrowseNext

BrowseResponse browse(const AddressSpace& space, const BrowseRequest& request, ServiceContext& ctx) {
  BrowseResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  auto& header = response.response_header;
  if (!detail::check_operation_count("Browse", request.nodes_to_browse.size(),
                                     ctx.limits.max_nodes_per_browse, header)) {
    return response;
  }
  if (!request.view.view_id.is_null() && space.find_as<ViewNode>(request.view.view_id) == nullptr) {
    header.service_result = status::BadViewIdUnknown;
    logger()->debug("Browse: unknown view {}", to_string(request.view.view_id));
    return response;
  }
  const std::uint32_t max = max_references(request.requested_max_references_per_node, ctx.limits);
  for (const auto& description : request.nodes_to_browse) {
    BrowseResult& result = response.results.emplace_back();
    std::vector<ReferenceDescription> all;
    result.status_code = collect(space, description, ctx.user, all);
    if (result.status_code.is_bad()) {
      logger()->debug("Browse {}: {}", to_string(description.node_id), to_string(result.status_code));
      continue;
    }
    page(std::move(all), max, ctx.continuations, result);
  }
  return response;
}

BrowseNextResponse browse_next(const AddressSpace& /*space*/, const BrowseNextRequest& request,
                               ServiceContext& ctx) {
  BrowseNextResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  if (!detail::check_operation_count("BrowseNext", request.continuation_points.size(),
                                     ctx.limits.max_nodes_per_browse, response.response_header)) {
    return response;
  }
  for (const auto& point : request.continuation_points) {
    BrowseResult& result = response.results.emplace_back();
    auto pending = ctx.continuations != nullptr ? ctx.continuations->take(point) : std::nullopt;
    if (!pending) {
      result.status_code = status::BadContinuationPointInvalid;
      logger()->debug("BrowseNext: unknown continuation point");
      continue;
    }
    if (request.release_continuation_points) {
      continue;  // taken, i.e. released
    }
    page(std::move(pending->remaining), pending->max_references, ctx.continuations, result);
  }
  return response;
}

// ---- TranslateBrowsePathsToNodeIds

BrowsePathResult translate_browse_path(const AddressSpace& space, const BrowsePath& path) {
  BrowsePathResult result;
  const auto& elements = path.relative_path.elements;
  if (!space.contains(path.starting_node)) {
    result.status_code = status::BadNodeIdUnknown;
    return result;
  }
  if (elements.empty()) {
    result.status_code = status::BadNothingToDo;
    return result;
  }
  // OPC 10000-4 §5.8.4.2: every element, the last one included, names its target.
  for (const auto& e : elements) {
    if (e.target_name.name.empty()) {
      result.status_code = status::BadBrowseNameInvalid;
      return result;
    }
  }
  std::vector<NodeId> current{path.starting_node};
  for (const auto& e : elements) {
    std::vector<NodeId> next;
    for (const auto& id : current) {
      for (const auto& r : space.find(id)->references) {
        if (r.is_forward == e.is_inverse ||
            !type_matches(space, r.reference_type_id, e.reference_type_id, e.include_subtypes)) {
          continue;
        }
        const Node* target = space.find(r.target_id);
        if (target != nullptr && target->browse_name == e.target_name &&
            std::find(next.begin(), next.end(), r.target_id) == next.end()) {
          next.push_back(r.target_id);
        }
      }
    }
    if (next.empty()) {
      result.status_code = status::BadNoMatch;
      return result;
    }
    current = std::move(next);
  }
  for (const auto& id : current) {
    BrowsePathTarget& target = result.targets.emplace_back();
    target.target_id.node_id = id;
    // UInt32 max: the target completes the path (OPC 10000-4 §5.8.4.2).
    target.remaining_path_index = std::numeric_limits<std::uint32_t>::max();
  }
  return result;
}

TranslateBrowsePathsToNodeIdsResponse translate_browse_paths(
    const AddressSpace& space, const TranslateBrowsePathsToNodeIdsRequest& request, ServiceContext& ctx) {
  TranslateBrowsePathsToNodeIdsResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  if (!detail::check_operation_count("TranslateBrowsePathsToNodeIds", request.browse_paths.size(),
                                     ctx.limits.max_nodes_per_translate_browse_paths,
                                     response.response_header)) {
    return response;
  }
  for (const auto& path : request.browse_paths) {
    response.results.push_back(translate_browse_path(space, path));
    if (response.results.back().status_code.is_bad()) {
      logger()->debug("TranslateBrowsePaths from {}: {}", to_string(path.starting_node),
                      to_string(response.results.back().status_code));
    }
  }
  return response;
}

// ---- RegisterNodes / UnregisterNodes (OPC 10000-4 §5.8.5, §5.8.6): no aliases, the ids are
// returned as they are.

RegisterNodesResponse register_nodes(const AddressSpace& /*space*/, const RegisterNodesRequest& request,
                                     ServiceContext& ctx) {
  RegisterNodesResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  if (!detail::check_operation_count("RegisterNodes", request.nodes_to_register.size(),
                                     ctx.limits.max_nodes_per_register_nodes, response.response_header)) {
    return response;
  }
  response.registered_node_ids = request.nodes_to_register;
  return response;
}

UnregisterNodesResponse unregister_nodes(const AddressSpace& /*space*/, const UnregisterNodesRequest& request,
                                         ServiceContext& ctx) {
  UnregisterNodesResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  detail::check_operation_count("UnregisterNodes", request.nodes_to_unregister.size(),
                                ctx.limits.max_nodes_per_register_nodes, response.response_header);
  return response;
}

}  // namespace sf::opcua::server
