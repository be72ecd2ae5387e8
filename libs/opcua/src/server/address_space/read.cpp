// The Read service (OPC 10000-4 §5.10.2): every attribute of every NodeClass (OPC 10000-3 §5.9
// Table 7), IndexRange, DataEncoding, TimestampsToReturn and maxAge.
#include <optional>

#include "server/address_space/service_util.hpp"

namespace sf::opcua::server {

namespace {

using detail::logger;

Error attribute_invalid(const Node& node, AttributeId attribute) {
  return status_error(status::BadAttributeIdInvalid, to_string(node.node_class()) + " " +
                                                         to_string(node.node_id) + " has no " +
                                                         std::string(attribute_name(attribute)));
}

Variant dimensions_variant(const std::vector<std::uint32_t>& dims) {
  // An absent ArrayDimensions reads as a null array (OPC 10000-3 §5.6.2).
  return dims.empty() ? Variant(Array<std::uint32_t>::null()) : Variant(Array<std::uint32_t>(dims));
}

std::uint8_t user_access_level(const VariableNode& v, const UserContext* user) {
  auto level = static_cast<std::uint8_t>(v.access_level & v.user_access_level);
  if (user != nullptr && !user->can_read(v)) {
    level = static_cast<std::uint8_t>(level & ~access_level::CurrentRead);
  }
  if (user != nullptr && !user->can_write(v, AttributeId::Value)) {
    level = static_cast<std::uint8_t>(level & ~access_level::CurrentWrite);
  }
  return level;
}

// Attributes of Variables and VariableTypes.
std::optional<Variant> variable_attribute(const Node& node, AttributeId attribute, const UserContext* user) {
  if (const auto* v = node.as<VariableNode>()) {
    switch (attribute) {
      case AttributeId::DataType:
        return Variant(v->data_type);
      case AttributeId::ValueRank:
        return Variant(v->value_rank);
      case AttributeId::ArrayDimensions:
        return dimensions_variant(v->array_dimensions);
      case AttributeId::AccessLevel:
        return Variant(v->access_level);
      case AttributeId::UserAccessLevel:
        return Variant(user_access_level(*v, user));
      case AttributeId::MinimumSamplingInterval:
        return Variant(v->minimum_sampling_interval);
      case AttributeId::Historizing:
        return Variant(v->historizing);
      case AttributeId::AccessLevelEx:
        return Variant(std::uint32_t{v->access_level} | (v->access_level_ex & ~std::uint32_t{0xFF}));
      default:
        return std::nullopt;
    }
  }
  if (const auto* t = node.as<VariableTypeNode>()) {
    switch (attribute) {
      case AttributeId::DataType:
        return Variant(t->data_type);
      case AttributeId::ValueRank:
        return Variant(t->value_rank);
      case AttributeId::ArrayDimensions:
        return dimensions_variant(t->array_dimensions);
      case AttributeId::IsAbstract:
        return Variant(t->is_abstract);
      default:
        return std::nullopt;
    }
  }
  return std::nullopt;
}

// The class-specific attributes other than Value (OPC 10000-3 §5.9 Table 7).
std::optional<Variant> class_attribute(const Node& node, AttributeId attribute, const UserContext* user) {
  if (auto v = variable_attribute(node, attribute, user)) {
    return v;
  }
  if (const auto* o = node.as<ObjectNode>(); o != nullptr && attribute == AttributeId::EventNotifier) {
    return Variant(o->event_notifier);
  }
  if (const auto* m = node.as<MethodNode>()) {
    if (attribute == AttributeId::Executable) {
      return Variant(m->executable);
    }
    if (attribute == AttributeId::UserExecutable) {
      return Variant(m->executable && m->user_executable && (user == nullptr || user->can_call(*m)));
    }
  }
  if (const auto* t = node.as<ObjectTypeNode>(); t != nullptr && attribute == AttributeId::IsAbstract) {
    return Variant(t->is_abstract);
  }
  if (const auto* t = node.as<DataTypeNode>(); t != nullptr && attribute == AttributeId::IsAbstract) {
    return Variant(t->is_abstract);
  }
  if (const auto* r = node.as<ReferenceTypeNode>()) {
    switch (attribute) {
      case AttributeId::IsAbstract:
        return Variant(r->is_abstract);
      case AttributeId::Symmetric:
        return Variant(r->symmetric);
      case AttributeId::InverseName:
        // Optional for symmetric and abstract types (OPC 10000-3 §5.3.3.2).
        return r->inverse_name.text.is_null() && r->symmetric ? std::nullopt
                                                              : std::optional(Variant(r->inverse_name));
      default:
        return std::nullopt;
    }
  }
  if (const auto* view = node.as<ViewNode>()) {
    if (attribute == AttributeId::ContainsNoLoops) {
      return Variant(view->contains_no_loops);
    }
    if (attribute == AttributeId::EventNotifier) {
      return Variant(view->event_notifier);
    }
  }
  return std::nullopt;
}

// Every attribute but Value.
Result<Variant> node_attribute(const Node& node, AttributeId attribute, const UserContext* user) {
  switch (attribute) {
    case AttributeId::NodeId:
      return Variant(node.node_id);
    case AttributeId::NodeClass:
      return Variant(static_cast<std::int32_t>(node.node_class()));
    case AttributeId::BrowseName:
      return Variant(node.browse_name);
    case AttributeId::DisplayName:
      return Variant(node.display_name);
    case AttributeId::Description:
      return Variant(node.description);
    case AttributeId::WriteMask:
      return Variant(node.write_mask);
    case AttributeId::UserWriteMask:
      return Variant((user == nullptr || user->can_write(node, AttributeId::WriteMask))
                         ? node.write_mask & node.user_write_mask
                         : std::uint32_t{0});
    default:
      break;
  }
  if (auto v = class_attribute(node, attribute, user)) {
    return *std::move(v);
  }
  return attribute_invalid(node, attribute);
}

// The Value attribute: access checks, the reader callback or the stored value.
Result<DataValue> value_attribute(const Node& node, const UserContext* user) {
  if (const auto* v = node.as<VariableNode>()) {
    if ((v->access_level & access_level::CurrentRead) == 0) {
      return status_error(status::BadNotReadable, to_string(node.node_id) + " is not readable");
    }
    // Only the read half of user_access_level: asking the user's roles about writing too would
    // double the cost of every value read.
    if ((v->user_access_level & access_level::CurrentRead) == 0 || (user != nullptr && !user->can_read(*v))) {
      return status_error(status::BadUserAccessDenied,
                          to_string(node.node_id) + " is not readable by the user");
    }
    return v->reader ? v->reader() : v->value;
  }
  if (const auto* t = node.as<VariableTypeNode>()) {
    return t->value;
  }
  return attribute_invalid(node, AttributeId::Value);
}

Result<DataValue> attribute_value(const Node& node, AttributeId attribute, const UserContext* user) {
  if (attribute == AttributeId::Value) {
    return value_attribute(node, user);
  }
  auto plain = node_attribute(node, attribute, user);
  if (!plain) {
    return plain.error();
  }
  return DataValue(*std::move(plain));
}

// OPC 10000-4 §5.10.2.2: only the default binary encoding of structures exists here.
StatusCode check_data_encoding(const QualifiedName& encoding, AttributeId attribute) {
  if (encoding.name.empty()) {
    return {};
  }
  if (attribute != AttributeId::Value) {
    return status::BadDataEncodingInvalid;
  }
  if (encoding.namespace_index != 0 || encoding.name != "Default Binary") {
    return status::BadDataEncodingUnsupported;
  }
  return {};
}

DataValue bad(StatusCode code) {
  DataValue v;
  v.status = code;
  return v;
}

// One Read operation with the server timestamp of its request (one clock read per request).
DataValue read_one(const AddressSpace& space, const ReadValueId& item, TimestampsToReturn timestamps,
                   const ServiceContext& ctx, DateTime server_time) {
  const Node* node = space.find(item.node_id);
  const auto attribute = static_cast<AttributeId>(item.attribute_id);
  StatusCode failed;
  if (node == nullptr) {
    failed = status::BadNodeIdUnknown;
  } else if (item.attribute_id == 0 || item.attribute_id > kMaxAttributeId) {
    failed = status::BadAttributeIdInvalid;
  } else {
    failed = check_data_encoding(item.data_encoding, attribute);
  }
  auto range = parse_numeric_range(item.index_range);
  if (failed.is_good() && !range) {
    failed = status_of(range.error());
  }
  if (failed.is_bad()) {
    logger()->debug("Read {} attribute {}: {}", to_string(item.node_id), item.attribute_id,
                    to_string(failed));
    return bad(failed);
  }
  Result<DataValue> value = attribute_value(*node, attribute, ctx.user);
  if (!value) {
    logger()->debug("Read {} {}: {}", to_string(item.node_id), attribute_name(attribute),
                    value.error().message);
    return bad(status_of(value.error()));
  }
  DataValue result = *std::move(value);
  if (!range->empty() && !result.value.is_empty()) {
    auto sub = apply_numeric_range(result.value, *range);
    if (!sub) {
      logger()->debug("Read {} {}: {}", to_string(item.node_id), attribute_name(attribute),
                      sub.error().message);
      return bad(status_of(sub.error()));
    }
    result.value = *std::move(sub);
  }
  // OPC 10000-4 §5.10.2.2: source timestamps belong to Values only; server timestamps are ours.
  const bool want_source = timestamps == TimestampsToReturn::Source || timestamps == TimestampsToReturn::Both;
  const bool want_server = timestamps == TimestampsToReturn::Server || timestamps == TimestampsToReturn::Both;
  if (!want_source || attribute != AttributeId::Value) {
    result.source_timestamp = DateTime();
    result.source_picoseconds = 0;
  }
  result.server_timestamp = want_server ? server_time : DateTime();
  result.server_picoseconds = 0;
  return result;
}

}  // namespace

DataValue read_attribute(const AddressSpace& space, const ReadValueId& item, TimestampsToReturn timestamps,
                         const ServiceContext& ctx) {
  return read_one(space, item, timestamps, ctx, detail::now(ctx));
}

ReadResponse read(AddressSpace& space, const ReadRequest& request, ServiceContext& ctx) {
  ReadResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  auto& header = response.response_header;
  if (!detail::check_operation_count("Read", request.nodes_to_read.size(), ctx.limits.max_nodes_per_read,
                                     header)) {
    return response;
  }
  if (request.max_age < 0.0) {
    header.service_result = status::BadMaxAgeInvalid;
    logger()->debug("Read: maxAge {} is negative", request.max_age);
    return response;
  }
  const auto timestamps = static_cast<std::int32_t>(request.timestamps_to_return);
  if (timestamps < 0 || timestamps > static_cast<std::int32_t>(TimestampsToReturn::Neither)) {
    header.service_result = status::BadTimestampsToReturnInvalid;
    logger()->debug("Read: timestampsToReturn {} is invalid", timestamps);
    return response;
  }
  // maxAge: every read returns the current value (there is no cache to be older than it).
  response.results.reserve(request.nodes_to_read.size());
  for (const auto& item : request.nodes_to_read) {
    response.results.push_back(
        read_one(space, item, request.timestamps_to_return, ctx, response.response_header.timestamp));
  }
  return response;
}

}  // namespace sf::opcua::server
