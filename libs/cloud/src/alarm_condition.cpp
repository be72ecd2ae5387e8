// Alarms as OPC 10000-9 condition events (alarm_condition.hpp).
#include "alarm_condition.hpp"

#include <fmt/format.h>

#include "sf/cloud/value_mapping.hpp"
#include "sf/opcua/node_ids.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::cloud::detail {

namespace {

namespace ua = sf::opcua;

// A TwoStateVariable (OPC 10000-9 §5.3.1 and §5.8.2): its text and its Id.
void two_state(std::map<std::string, ua::Variant>& fields, const std::string& name, bool id,
               std::string_view true_text, std::string_view false_text) {
  fields[name] = ua::Variant(ua::LocalizedText("en", ua::String(id ? true_text : false_text)));
  fields[name + "/Id"] = ua::Variant(id);
}

}  // namespace

ua::SubscriptionService::Event condition_event(const Alarm& alarm, std::uint16_t ns) {
  const historian::Event h = alarm_event(alarm, kKnowledgeServer);
  ua::SubscriptionService::Event e;
  e.event_type = ua::NodeId(0, kAlarmConditionType);
  auto& f = e.fields;
  f["EventId"] = ua::Variant(ua::ByteString(h.event_id));
  f["EventType"] = ua::Variant(e.event_type);
  f["SourceNode"] = ua::Variant(ua::NodeId(0, ua::id::Server));
  f["SourceName"] = ua::Variant(h.source_name);
  f["Time"] = ua::Variant(to_date_time(h.time));
  f["ReceiveTime"] = ua::Variant(to_date_time(h.receive_time));
  f["Message"] = ua::Variant(ua::LocalizedText("en", ua::String(h.message)));
  f["Severity"] = ua::Variant(h.severity);
  f["ConditionId"] = ua::Variant(ua::NodeId(ns, ua::String(fmt::format("knowledge/{}", alarm.id))));
  f["ConditionClassId"] = ua::Variant(ua::NodeId(0, kBaseConditionClassType));
  f["ConditionClassName"] = ua::Variant(ua::LocalizedText("en", "BaseConditionClass"));
  f["ConditionName"] = ua::Variant(alarm.rule);
  f["BranchId"] = ua::Variant(ua::NodeId());
  // §5.5.2: Retain while the condition is of interest — active, or waiting for an operator.
  f["Retain"] = ua::Variant(alarm.active || !alarm.acked);
  two_state(f, "EnabledState", true, "Enabled", "Disabled");
  f["Quality"] = ua::Variant(ua::StatusCode(ua::status::Good));
  f["LastSeverity"] = ua::Variant(h.severity);
  f["Comment"] = ua::Variant(ua::LocalizedText("en", ua::String(alarm.ack_comment)));
  f["ClientUserId"] = ua::Variant(alarm.acked_by);
  two_state(f, "AckedState", alarm.acked, "Acknowledged", "Unacknowledged");
  two_state(f, "ActiveState", alarm.active, "Active", "Inactive");
  return e;
}

}  // namespace sf::cloud::detail
