// The Write service (OPC 10000-4 §5.10.4): Values with AccessLevel/UserAccessLevel checks, type
// checks and IndexRange; other attributes as far as WriteMask/UserWriteMask allow.
#include "server/address_space/service_util.hpp"

namespace sf::opcua::server {

namespace {

using detail::logger;

// The WriteMask bit of an attribute (OPC 10000-3 §8.60); 0 for attributes never writable here.
std::uint32_t write_mask_bit(AttributeId attribute, NodeClass node_class) {
  switch (attribute) {
    case AttributeId::AccessLevel:
      return write_mask::AccessLevel;
    case AttributeId::ArrayDimensions:
      return write_mask::ArrayDimensions;
    case AttributeId::BrowseName:
      return write_mask::BrowseName;
    case AttributeId::ContainsNoLoops:
      return write_mask::ContainsNoLoops;
    case AttributeId::DataType:
      return write_mask::DataType;
    case AttributeId::Description:
      return write_mask::Description;
    case AttributeId::DisplayName:
      return write_mask::DisplayName;
    case AttributeId::EventNotifier:
      return write_mask::EventNotifier;
    case AttributeId::Executable:
      return write_mask::Executable;
    case AttributeId::Historizing:
      return write_mask::Historizing;
    case AttributeId::InverseName:
      return write_mask::InverseName;
    case AttributeId::IsAbstract:
      return write_mask::IsAbstract;
    case AttributeId::MinimumSamplingInterval:
      return write_mask::MinimumSamplingInterval;
    case AttributeId::Symmetric:
      return write_mask::Symmetric;
    case AttributeId::UserAccessLevel:
      return write_mask::UserAccessLevel;
    case AttributeId::UserExecutable:
      return write_mask::UserExecutable;
    case AttributeId::UserWriteMask:
      return write_mask::UserWriteMask;
    case AttributeId::ValueRank:
      return write_mask::ValueRank;
    case AttributeId::WriteMask:
      return write_mask::WriteMask;
    case AttributeId::AccessLevelEx:
      return write_mask::AccessLevelEx;
    case AttributeId::Value:
      return node_class == NodeClass::VariableType ? write_mask::ValueForVariableType : 0;
    default:
      return 0;
  }
}

// Whether the node class has the attribute (OPC 10000-3 §5.9 Table 7), for the attributes
// this server stores.
bool has_attribute(const Node& node, AttributeId attribute) {
  const auto c = node.node_class();
  switch (attribute) {
    case AttributeId::NodeId:
    case AttributeId::NodeClass:
    case AttributeId::BrowseName:
    case AttributeId::DisplayName:
    case AttributeId::Description:
    case AttributeId::WriteMask:
    case AttributeId::UserWriteMask:
      return true;
    case AttributeId::IsAbstract:
      return c == NodeClass::ObjectType || c == NodeClass::VariableType || c == NodeClass::ReferenceType ||
             c == NodeClass::DataType;
    case AttributeId::Symmetric:
    case AttributeId::InverseName:
      return c == NodeClass::ReferenceType;
    case AttributeId::ContainsNoLoops:
      return c == NodeClass::View;
    case AttributeId::EventNotifier:
      return c == NodeClass::Object || c == NodeClass::View;
    case AttributeId::Value:
    case AttributeId::DataType:
    case AttributeId::ValueRank:
    case AttributeId::ArrayDimensions:
      return c == NodeClass::Variable || c == NodeClass::VariableType;
    case AttributeId::AccessLevel:
    case AttributeId::UserAccessLevel:
    case AttributeId::MinimumSamplingInterval:
    case AttributeId::Historizing:
    case AttributeId::AccessLevelEx:
      return c == NodeClass::Variable;
    case AttributeId::Executable:
    case AttributeId::UserExecutable:
      return c == NodeClass::Method;
    default:
      return false;
  }
}

template <typename T>
StatusCode take(const Variant& v, T& out) {
  const T* value = v.get_if<T>();
  if (value == nullptr) {
    return status::BadTypeMismatch;
  }
  out = *value;
  return {};
}

StatusCode take_dimensions(const Variant& v, std::vector<std::uint32_t>& out) {
  const auto* dims = v.array_if<std::uint32_t>();
  if (dims == nullptr) {
    return status::BadTypeMismatch;
  }
  out.assign(dims->begin(), dims->end());
  return {};
}

StatusCode write_variable_attribute(AddressSpace& space, VariableNode& v, AttributeId attribute,
                                    const Variant& x) {
  switch (attribute) {
    case AttributeId::DataType: {
      NodeId type;
      if (auto st = take(x, type); st.is_bad()) {
        return st;
      }
      if (space.find_as<DataTypeNode>(type) == nullptr) {
        return status::BadTypeMismatch;
      }
      v.data_type = type;
      return {};
    }
    case AttributeId::ValueRank:
      return take(x, v.value_rank);
    case AttributeId::ArrayDimensions:
      return take_dimensions(x, v.array_dimensions);
    case AttributeId::AccessLevel:
      return take(x, v.access_level);
    case AttributeId::UserAccessLevel:
      return take(x, v.user_access_level);
    case AttributeId::MinimumSamplingInterval:
      return take(x, v.minimum_sampling_interval);
    case AttributeId::Historizing:
      return take(x, v.historizing);
    case AttributeId::AccessLevelEx: {
      std::uint32_t ex = 0;
      if (auto st = take(x, ex); st.is_bad()) {
        return st;
      }
      v.access_level = static_cast<std::uint8_t>(ex & 0xFFU);
      v.access_level_ex = ex & ~std::uint32_t{0xFF};
      return {};
    }
    default:
      return status::BadNotWritable;
  }
}

// Attributes other than Value, after the WriteMask checks.
StatusCode write_plain_attribute(AddressSpace& space, Node& node, AttributeId attribute, const Variant& x) {
  switch (attribute) {
    case AttributeId::BrowseName:
      return take(x, node.browse_name);
    case AttributeId::DisplayName:
      return take(x, node.display_name);
    case AttributeId::Description:
      return take(x, node.description);
    case AttributeId::WriteMask:
      return take(x, node.write_mask);
    case AttributeId::UserWriteMask:
      return take(x, node.user_write_mask);
    default:
      break;
  }
  if (auto* v = node.as<VariableNode>()) {
    return write_variable_attribute(space, *v, attribute, x);
  }
  if (auto* t = node.as<VariableTypeNode>()) {
    switch (attribute) {
      case AttributeId::DataType:
        return take(x, t->data_type);
      case AttributeId::ValueRank:
        return take(x, t->value_rank);
      case AttributeId::ArrayDimensions:
        return take_dimensions(x, t->array_dimensions);
      case AttributeId::IsAbstract:
        return take(x, t->is_abstract);
      default:
        return status::BadNotWritable;
    }
  }
  if (auto* o = node.as<ObjectNode>(); o != nullptr && attribute == AttributeId::EventNotifier) {
    return take(x, o->event_notifier);
  }
  if (auto* m = node.as<MethodNode>()) {
    return take(x, attribute == AttributeId::Executable ? m->executable : m->user_executable);
  }
  if (auto* t = node.as<ObjectTypeNode>(); t != nullptr && attribute == AttributeId::IsAbstract) {
    return take(x, t->is_abstract);
  }
  if (auto* t = node.as<DataTypeNode>(); t != nullptr && attribute == AttributeId::IsAbstract) {
    return take(x, t->is_abstract);
  }
  if (auto* r = node.as<ReferenceTypeNode>()) {
    if (attribute == AttributeId::IsAbstract) {
      return take(x, r->is_abstract);
    }
    return attribute == AttributeId::Symmetric ? take(x, r->symmetric) : take(x, r->inverse_name);
  }
  if (auto* view = node.as<ViewNode>()) {
    return attribute == AttributeId::ContainsNoLoops ? take(x, view->contains_no_loops)
                                                     : take(x, view->event_notifier);
  }
  return status::BadNotWritable;
}

// OPC 10000-4 §5.10.4.1: status and timestamps are written only where AccessLevel allows it.
StatusCode check_value_extras(const DataValue& value, std::uint8_t level) {
  if (value.status.value() != 0 && (level & access_level::StatusWrite) == 0) {
    return status::BadWriteNotSupported;
  }
  const bool timestamps = !value.source_timestamp.is_min() || !value.server_timestamp.is_min();
  if (timestamps && (level & access_level::TimestampWrite) == 0) {
    return status::BadWriteNotSupported;
  }
  return {};
}

StatusCode write_value(AddressSpace& space, Node& node, const WriteValue& item, const NumericRange& range,
                       const ServiceContext& ctx) {
  auto* variable = node.as<VariableNode>();
  auto* type = node.as<VariableTypeNode>();
  const NodeId& data_type = variable != nullptr ? variable->data_type : type->data_type;
  const std::int32_t rank = variable != nullptr ? variable->value_rank : type->value_rank;
  const auto& dims = variable != nullptr ? variable->array_dimensions : type->array_dimensions;
  if (variable != nullptr) {
    if ((variable->access_level & access_level::CurrentWrite) == 0) {
      return status::BadNotWritable;
    }
    if ((variable->user_access_level & access_level::CurrentWrite) == 0 ||
        (ctx.user != nullptr && !ctx.user->can_write(node, AttributeId::Value))) {
      return status::BadUserAccessDenied;
    }
    if (auto st = check_value_extras(item.value, variable->access_level); st.is_bad()) {
      return st;
    }
  }
  DataValue next = item.value;
  if (!range.empty()) {
    auto current = space.value(node.node_id);
    if (!current) {
      return status_of(current.error());
    }
    // The patch has the element type of the whole value; its shape comes from the range.
    if (auto st = detail::check_value(space, item.value.value, data_type, value_rank::Any, {}); st.is_bad()) {
      return st;
    }
    auto patched = write_numeric_range(current->value, range, item.value.value);
    if (!patched) {
      return status_of(patched.error());
    }
    next.value = *std::move(patched);
  } else if (auto st = detail::check_value(space, next.value, data_type, rank, dims); st.is_bad()) {
    return st;
  }
  if (next.source_timestamp.is_min()) {
    next.source_timestamp = detail::now(ctx);
  }
  next.server_timestamp = detail::now(ctx);
  if (variable != nullptr && variable->writer) {
    const StatusCode result = variable->writer(next);
    if (result.is_bad()) {
      return result;
    }
  }
  if (variable != nullptr) {
    variable->value = std::move(next);
  } else {
    type->value = std::move(next);
  }
  return {};
}

}  // namespace

StatusCode write_attribute(AddressSpace& space, const WriteValue& item, const ServiceContext& ctx) {
  Node* node = space.find_mutable(item.node_id);
  const auto attribute = static_cast<AttributeId>(item.attribute_id);
  StatusCode result;
  auto range = parse_numeric_range(item.index_range);
  if (node == nullptr) {
    result = status::BadNodeIdUnknown;
  } else if (item.attribute_id == 0 || item.attribute_id > kMaxAttributeId ||
             !has_attribute(*node, attribute)) {
    result = status::BadAttributeIdInvalid;
  } else if (!range) {
    result = status_of(range.error());
  } else if (attribute == AttributeId::Value && node->node_class() == NodeClass::Variable) {
    result = write_value(space, *node, item, *range, ctx);
  } else {
    const std::uint32_t bit = write_mask_bit(attribute, node->node_class());
    if (bit == 0 || (node->write_mask & bit) == 0) {
      result = status::BadNotWritable;
    } else if ((node->user_write_mask & bit) == 0 ||
               (ctx.user != nullptr && !ctx.user->can_write(*node, attribute))) {
      result = status::BadUserAccessDenied;
    } else if (attribute == AttributeId::Value) {
      result = write_value(space, *node, item, *range, ctx);
    } else if (!range->empty()) {
      result = status::BadWriteNotSupported;  // IndexRange writes exist for Values only
    } else {
      result = write_plain_attribute(space, *node, attribute, item.value.value);
    }
  }
  if (result.is_bad()) {
    logger()->debug("Write {} attribute {}: {}", to_string(item.node_id), item.attribute_id,
                    to_string(result));
    return result;
  }
  space.notify({NodeChange::Kind::AttributeWritten, item.node_id, attribute});
  return result;
}

WriteResponse write(AddressSpace& space, const WriteRequest& request, ServiceContext& ctx) {
  WriteResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  if (!detail::check_operation_count("Write", request.nodes_to_write.size(), ctx.limits.max_nodes_per_write,
                                     response.response_header)) {
    return response;
  }
  response.results.reserve(request.nodes_to_write.size());
  for (const auto& item : request.nodes_to_write) {
    response.results.push_back(write_attribute(space, item, ctx));
  }
  return response;
}

}  // namespace sf::opcua::server
