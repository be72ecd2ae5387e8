// An alarm of the knowledge loop as the event of an OPC UA Alarms & Conditions condition (OPC
// 10000-9 §5.8 AlarmConditionType), reported by the aggregating server's Server object. Each
// raise, clear and acknowledgement is one event; the condition itself is not a node of the
// address space (its ConditionId names it), so clients see it through events only, and through
// ConditionRefresh (§5.5.7) the retained ones again.
#pragma once

#include <cstdint>

#include "sf/cloud/knowledge_loop.hpp"
#include "sf/opcua/server/subscriptions.hpp"

namespace sf::cloud::detail {

// Namespace-0 NodeIds of OPC 10000-9 (NodeIds.csv of the OPC Foundation).
inline constexpr std::uint32_t kConditionType = 2782;
inline constexpr std::uint32_t kAlarmConditionType = 2915;
inline constexpr std::uint32_t kBaseConditionClassType = 11163;

// The event's fields by browse path (OPC 10000-9 §5.5.2 ConditionType, §5.7.2
// AcknowledgeableConditionType, §5.8.2 AlarmConditionType): EventId, EventType, SourceNode
// (the Server object), SourceName (the individual's local name), Time, ReceiveTime, Message,
// Severity, ConditionId (ns=`ns`;s=knowledge/<alarm id>), ConditionClassId, ConditionName (the
// rule), BranchId (null), Retain (active or not yet acknowledged), EnabledState, Quality,
// Comment and ClientUserId (of the acknowledgement), AckedState, ActiveState (with /Id).
opcua::SubscriptionService::Event condition_event(const Alarm& alarm, std::uint16_t ns);

}  // namespace sf::cloud::detail
