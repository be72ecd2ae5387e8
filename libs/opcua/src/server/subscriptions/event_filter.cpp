// EventFilter validation and select clauses (OPC 10000-4 §7.17.3, §7.4.4.5).
#include "server/subscriptions/event_filter.hpp"

#include <string>

#include "sf/opcua/node_ids.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::subs {
namespace {

constexpr std::uint32_t kAttributeNodeId = 1;
constexpr std::uint32_t kAttributeValue = 13;

const NodeId& base_event_type() {
  static const NodeId id(0, opcua::id::BaseEventType);
  return id;
}

// "Prop/Child": the key of Event::fields for a browse path.
std::string field_key(const Array<QualifiedName>& path) {
  std::string key;
  for (const auto& name : path) {
    if (!key.empty()) {
      key += '/';
    }
    key += name.name.str();
  }
  return key;
}

}  // namespace

bool TypeTree::derives(const NodeId& type, const NodeId& base) const {
  if (base.is_null() || base == base_event_type() || type == base) {
    return true;
  }
  return is_subtype_ ? is_subtype_(type, base) : false;
}

bool TypeTree::is_event_type(const NodeId& type) const {
  if (type.is_null() || type == base_event_type() || !is_subtype_) {
    return true;
  }
  return is_subtype_(type, base_event_type());
}

StatusCode check_simple_operand(const SimpleAttributeOperand& operand, const TypeTree& types) {
  // §7.17.3: the type must be BaseEventType or one of its subtypes.
  if (!types.is_event_type(operand.type_definition_id)) {
    return status::BadTypeDefinitionInvalid;
  }
  for (const auto& name : operand.browse_path) {
    if (name.name.empty()) {
      return status::BadBrowseNameInvalid;
    }
  }
  if (operand.attribute_id == kAttributeNodeId) {
    // The NodeId of a Condition: an empty path on a ConditionType (the ConditionId field).
    return operand.browse_path.empty() ? status::Good : status::BadAttributeIdInvalid;
  }
  if (operand.attribute_id != kAttributeValue) {
    return status::BadAttributeIdInvalid;
  }
  return operand.browse_path.empty() ? status::BadBrowseNameInvalid : status::Good;
}

Variant event_field(const Event& event, const SimpleAttributeOperand& operand, const TypeTree& types) {
  // §7.17.3: with BaseEventType the path is evaluated without considering the type; with
  // another type only events of that type (or a subtype) have the field.
  if (!types.derives(event.event_type, operand.type_definition_id)) {
    return {};
  }
  const std::string key =
      operand.attribute_id == kAttributeNodeId ? "ConditionId" : field_key(operand.browse_path);
  if (auto it = event.fields.find(key); it != event.fields.end()) {
    return it->second;
  }
  if (key == "EventType") {
    return Variant(event.event_type);
  }
  return {};
}

Array<Variant> select_fields(const CompiledEventFilter& filter, const Event& event, const TypeTree& types) {
  Array<Variant> fields;
  fields.reserve(filter.filter.select_clauses.size());
  for (std::size_t i = 0; i < filter.filter.select_clauses.size(); ++i) {
    fields.push_back(filter.select_status[i].is_good()
                         ? event_field(event, filter.filter.select_clauses[i], types)
                         : Variant{});
  }
  return fields;
}

EventFilterCheck check_event_filter(const EventFilter& filter, const TypeTree& types) {
  EventFilterCheck out;
  out.compiled.filter = filter;
  bool any_valid = false;
  for (const auto& clause : filter.select_clauses) {
    const StatusCode st = check_simple_operand(clause, types);
    out.compiled.select_status.push_back(st);
    out.result.select_clause_results.push_back(st);
    any_valid = any_valid || st.is_good();
    out.has_errors = out.has_errors || !st.is_good();
  }
  const bool where_ok = check_content_filter(filter.where_clause, types, out.result.where_clause_result);
  out.has_errors = out.has_errors || !where_ok;
  if (!where_ok || !any_valid) {
    out.status = status::BadEventFilterInvalid;
  }
  if (!out.has_errors) {
    out.result.select_clause_results.clear();
  }
  return out;
}

}  // namespace sf::opcua::subs
