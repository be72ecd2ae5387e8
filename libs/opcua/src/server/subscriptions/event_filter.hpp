// EventFilter (OPC 10000-4 §7.17.3) and its ContentFilter where clause (§7.4): validation into
// an EventFilterResult, the where clause evaluated against one event, the select clauses turned
// into the event's fields. Internal to the subscriptions engine.
#pragma once

#include <functional>
#include <vector>

#include "sf/opcua/server/subscriptions.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua::subs {

using Event = SubscriptionService::Event;

// The event type hierarchy as the callbacks tell it.
class TypeTree {
 public:
  explicit TypeTree(const std::function<bool(const NodeId&, const NodeId&)>& is_subtype)
      : is_subtype_(is_subtype) {}
  // `type` is `base` or derives from it; a null `base` means BaseEventType.
  [[nodiscard]] bool derives(const NodeId& type, const NodeId& base) const;
  // `type` is BaseEventType or one of its subtypes (null counts as BaseEventType; without the
  // callback every type is accepted).
  [[nodiscard]] bool is_event_type(const NodeId& type) const;

 private:
  const std::function<bool(const NodeId&, const NodeId&)>& is_subtype_;
};

// An EventFilter that passed validation, with the status of each select clause (a bad clause
// yields a null field, §7.17.3).
struct CompiledEventFilter {
  EventFilter filter;
  std::vector<StatusCode> select_status;
};

struct EventFilterCheck {
  // Good, or BadEventFilterInvalid (where clause invalid, or no valid select clause).
  StatusCode status;
  // Returned to the client when something in it is not Good.
  EventFilterResult result;
  bool has_errors = false;
  CompiledEventFilter compiled;
};
EventFilterCheck check_event_filter(const EventFilter& filter, const TypeTree& types);

// Validates one SimpleAttributeOperand (select clause or where-clause operand):
// BadTypeDefinitionInvalid, BadBrowseNameInvalid, BadAttributeIdInvalid, or Good.
StatusCode check_simple_operand(const SimpleAttributeOperand& operand, const TypeTree& types);

// The value the operand selects from the event; null when the event is not of the operand's
// type or has no such field.
Variant event_field(const Event& event, const SimpleAttributeOperand& operand, const TypeTree& types);

// The EventFieldList fields for the event.
Array<Variant> select_fields(const CompiledEventFilter& filter, const Event& event, const TypeTree& types);

// Validates the where clause into a ContentFilterResult; false when it has an error. An empty
// result (no elementResults) means all elements are Good.
bool check_content_filter(const ContentFilter& filter, const TypeTree& types, ContentFilterResult& result);

// Whether the event passes a validated where clause (an empty clause passes everything).
bool where_matches(const ContentFilter& filter, const Event& event, const TypeTree& types);

// §7.4.3 Like: '%' any run, '_' any one character, '[...]' / '[^...]' a set, '\' escapes.
bool like_matches(std::string_view text, std::string_view pattern);

}  // namespace sf::opcua::subs
