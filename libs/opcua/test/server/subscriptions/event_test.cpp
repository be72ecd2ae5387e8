// Events: select clauses, where clauses (ContentFilter operators), notifier routing, filter
// validation and event queue overflow.
#include <map>

#include "fixture.hpp"

namespace sf::opcua::subs_test {
namespace {

const NodeId kBaseEventType(0, id::BaseEventType);
const NodeId kMyEventType(1, String("MyEventType"));
const NodeId kSubEventType(1, String("SubEventType"));

SimpleAttributeOperand field(const char* name, NodeId type = kBaseEventType,
                             std::uint32_t attribute = kValue) {
  SimpleAttributeOperand o;
  o.type_definition_id = std::move(type);
  o.browse_path = {QualifiedName(0, name)};
  o.attribute_id = attribute;
  return o;
}

ExtensionObject attr(const char* name) {
  return ExtensionObject::make(field(name));
}
ExtensionObject lit(Variant v) {
  return ExtensionObject::make(LiteralOperand{std::move(v)});
}
ExtensionObject elem(std::uint32_t index) {
  return ExtensionObject::make(ElementOperand{index});
}
ContentFilterElement element(FilterOperator op, std::vector<ExtensionObject> operands) {
  ContentFilterElement e;
  e.filter_operator = op;
  e.filter_operands = std::move(operands);
  return e;
}

EventFilter event_filter(std::vector<SimpleAttributeOperand> select,
                         std::vector<ContentFilterElement> where = {}) {
  EventFilter f;
  f.select_clauses = std::move(select);
  f.where_clause.elements = std::move(where);
  return f;
}

SubscriptionService::Event event(NodeId type, std::map<std::string, Variant> fields) {
  return SubscriptionService::Event{std::move(type), std::move(fields)};
}

class SubsEvents : public SubscriptionsTest {
 protected:
  SubsEvents() {
    parent_type[kMyEventType] = kBaseEventType;
    parent_type[kSubEventType] = kMyEventType;
    nodes[node("Boiler")] = FakeNode{{}, true, true, {}};
    nodes[node("Tank")] = FakeNode{{}, true, true, {}};
    sub = create_sub(100, 10, 30);
  }

  MonitoredItemCreateResult event_item(std::uint32_t handle, EventFilter filter,
                                       const NodeId& notifier = NodeId(0, id::Server),
                                       std::uint32_t queue = 10, bool discard_oldest = true) {
    auto r = create_items(
        sub, {item_request(notifier, params(handle, 0, queue, discard_oldest, ExtensionObject::make(filter)),
                           MonitoringMode::Reporting, kEventNotifier)});
    EXPECT_EQ(r.response_header.service_result, status::Good);
    return r.results.at(0);
  }

  // Publishes once and returns each handle's events.
  std::map<std::uint32_t, std::vector<Array<Variant>>> collect() {
    publish(static_cast<std::uint32_t>(answers.size() + 1));
    advance(100);
    std::map<std::uint32_t, std::vector<Array<Variant>>> out;
    if (answers.empty()) {
      return out;
    }
    for (const auto& e : events(response(answers.size() - 1))) {
      out[e.client_handle].push_back(e.event_fields);
    }
    return out;
  }

  std::uint32_t sub = 0;
};

TEST_F(SubsEvents, SelectClausesPickFieldsByBrowsePath) {
  const auto r = event_item(5, event_filter({field("EventId"), field("EventType"), field("SourceName"),
                                             field("Severity"), field("Message"), field("NoSuchField")}));
  EXPECT_EQ(r.status_code, status::Good);
  EXPECT_EQ(r.revised_sampling_interval, 0);
  EXPECT_EQ(r.revised_queue_size, 10U);
  EXPECT_TRUE(r.filter_result.empty());
  svc->post_event(NodeId(0, id::Server),
                  event(kBaseEventType, {{"EventId", Variant(ByteString{1, 2})},
                                         {"SourceName", Variant("Boiler")},
                                         {"Severity", Variant(std::uint16_t{500})},
                                         {"Message", Variant(LocalizedText("en", "hot"))}}));
  const auto got = collect();
  ASSERT_EQ(got.size(), 1U);
  ASSERT_EQ(got.at(5).size(), 1U);
  EXPECT_EQ(got.at(5)[0],
            (Array<Variant>{Variant(ByteString{1, 2}), Variant(kBaseEventType), Variant("Boiler"),
                            Variant(std::uint16_t{500}), Variant(LocalizedText("en", "hot")), Variant{}}));
}

// OPC 10000-9 §5.5.7: RefreshStart, the retained conditions the where clause passes, RefreshEnd,
// on every event item of the session's subscription; the markers ignore the where clause.
TEST_F(SubsEvents, ConditionRefreshSendsTheRetainedConditionsBetweenItsMarkers) {
  EXPECT_EQ(svc->refresh_conditions(session(), sub, {}), status::BadNothingToDo);
  event_item(1, event_filter({field("EventType"), field("SourceName")}));
  event_item(2, event_filter({field("EventType"), field("EventId")},
                             {element(FilterOperator::OfType, {lit(kMyEventType)})}));
  const std::vector<SubscriptionService::Event> retained = {
      event(kMyEventType, {{"SourceName", Variant("boiler")}}),
      event(kBaseEventType, {{"SourceName", Variant("tank")}})};
  EXPECT_EQ(svc->refresh_conditions(other_session(), sub, retained), status::BadSubscriptionIdInvalid);
  EXPECT_EQ(svc->refresh_conditions(session(), sub + 100, retained), status::BadSubscriptionIdInvalid);
  ASSERT_EQ(svc->refresh_conditions(session(), sub, retained), status::Good);
  const auto got = collect();
  const Variant start(NodeId(0, 2787));
  const Variant end(NodeId(0, 2788));
  ASSERT_EQ(got.at(1).size(), 4U);
  EXPECT_EQ(got.at(1)[0], (Array<Variant>{start, Variant("Internal/ConditionRefresh")}));
  EXPECT_EQ(got.at(1)[1], (Array<Variant>{Variant(kMyEventType), Variant("boiler")}));
  EXPECT_EQ(got.at(1)[2], (Array<Variant>{Variant(kBaseEventType), Variant("tank")}));
  EXPECT_EQ(got.at(1)[3], (Array<Variant>{end, Variant("Internal/ConditionRefresh")}));
  // The where clause (OfType MyEventType) lets the boiler through, and the markers regardless.
  ASSERT_EQ(got.at(2).size(), 3U);
  EXPECT_EQ(got.at(2)[0][0], start);
  EXPECT_EQ(got.at(2)[1][0], Variant(kMyEventType));
  EXPECT_EQ(got.at(2)[2][0], end);
}

TEST_F(SubsEvents, TypedSelectClauseOnlyAppliesToThatType) {
  event_item(1, event_filter({field("SourceName"), field("Pressure", kMyEventType)}));
  svc->post_event(NodeId(0, id::Server),
                  event(kBaseEventType, {{"SourceName", Variant("a")}, {"Pressure", Variant(1.0)}}));
  svc->post_event(NodeId(0, id::Server),
                  event(kSubEventType, {{"SourceName", Variant("b")}, {"Pressure", Variant(2.0)}}));
  const auto got = collect();
  ASSERT_EQ(got.at(1).size(), 2U);
  EXPECT_EQ(got.at(1)[0], (Array<Variant>{Variant("a"), Variant{}}));
  EXPECT_EQ(got.at(1)[1], (Array<Variant>{Variant("b"), Variant(2.0)}));
}

TEST_F(SubsEvents, NotifierRouting) {
  const auto select = event_filter({field("SourceName")});
  event_item(1, select);  // Server: every event
  event_item(2, select, node("Boiler"));
  event_item(3, select, node("Tank"));
  svc->post_event(node("Boiler"), event(kBaseEventType, {{"SourceName", Variant("boiler event")}}));
  svc->post_event(NodeId(0, id::Server), event(kBaseEventType, {{"SourceName", Variant("server event")}}));
  const auto got = collect();
  EXPECT_EQ(got.at(1), (std::vector<Array<Variant>>{{Variant("boiler event")}, {Variant("server event")}}));
  EXPECT_EQ(got.at(2), (std::vector<Array<Variant>>{{Variant("boiler event")}}));
  EXPECT_FALSE(got.contains(3));
}

TEST_F(SubsEvents, WhereClauseWithAndOfTypeAndComparison) {
  event_item(1, event_filter({field("Severity")}, {element(FilterOperator::And, {elem(1), elem(2)}),
                                                   element(FilterOperator::GreaterThanOrEqual,
                                                           {attr("Severity"), lit(std::uint16_t{500})}),
                                                   element(FilterOperator::OfType, {lit(kMyEventType)})}));
  const NodeId server(0, id::Server);
  svc->post_event(server, event(kBaseEventType, {{"Severity", Variant(std::uint16_t{600})}}));
  svc->post_event(server, event(kMyEventType, {{"Severity", Variant(std::uint16_t{400})}}));
  svc->post_event(server, event(kSubEventType, {{"Severity", Variant(std::uint16_t{700})}}));
  svc->post_event(server, event(kMyEventType, {{"Severity", Variant(std::uint16_t{500})}}));
  const auto got = collect();
  EXPECT_EQ(got.at(1),
            (std::vector<Array<Variant>>{{Variant(std::uint16_t{700})}, {Variant(std::uint16_t{500})}}));
}

TEST_F(SubsEvents, Operators) {
  using F = FilterOperator;
  const std::vector<std::vector<ContentFilterElement>> wheres = {
      {element(F::Equals, {attr("SourceName"), lit("Valve")})},
      {element(F::Like, {attr("SourceName"), lit("Pump-_")})},
      {element(F::Like, {attr("SourceName"), lit("Pump%")})},
      {element(F::InList, {attr("Severity"), lit(std::uint16_t{100}), lit(std::uint16_t{800})})},
      {element(F::Not, {elem(1)}), element(F::LessThan, {attr("Severity"), lit(std::uint16_t{300})})},
      {element(F::IsNull, {attr("Severity")})},
      {element(F::Or, {elem(1), elem(2)}), element(F::Equals, {attr("SourceName"), lit("pump")}),
       element(F::GreaterThan, {attr("Severity"), lit(std::uint16_t{500})})},
      {element(F::Between, {attr("Severity"), lit(std::uint16_t{100}), lit(std::uint16_t{300})})},
      {element(F::Like, {attr("SourceName"), lit("[PV]%")})},
      {element(F::LessThanOrEqual, {attr("Severity"), lit(std::int32_t{300})})},
      {element(F::Equals, {attr("Severity"), lit("800")})},
      {element(F::Like, {attr("SourceName"), lit("%[^0-9]")})},
  };
  for (std::uint32_t i = 0; i < wheres.size(); ++i) {
    const auto r = event_item(i + 1, event_filter({field("SourceName")}, wheres[i]));
    ASSERT_EQ(r.status_code, status::Good) << "filter " << i + 1;
  }
  const NodeId server(0, id::Server);
  svc->post_event(server, event(kBaseEventType, {{"SourceName", Variant("Pump-1")},
                                                 {"Severity", Variant(std::uint16_t{100})}}));
  svc->post_event(server, event(kBaseEventType, {{"SourceName", Variant("Pump-22")},
                                                 {"Severity", Variant(std::uint16_t{300})}}));
  svc->post_event(server, event(kBaseEventType, {{"SourceName", Variant("Valve")},
                                                 {"Severity", Variant(std::uint16_t{800})}}));
  svc->post_event(server, event(kBaseEventType, {{"SourceName", Variant("pump")}}));
  const auto got = collect();
  auto names = [&](std::uint32_t handle) {
    std::vector<std::string> out;
    if (got.contains(handle)) {
      for (const auto& fields : got.at(handle)) {
        out.push_back(fields.at(0).get_if<String>()->str());
      }
    }
    return out;
  };
  using N = std::vector<std::string>;
  EXPECT_EQ(names(1), (N{"Valve"}));
  EXPECT_EQ(names(2), (N{"Pump-1"}));
  EXPECT_EQ(names(3), (N{"Pump-1", "Pump-22"}));
  EXPECT_EQ(names(4), (N{"Pump-1", "Valve"}));
  EXPECT_EQ(names(5), (N{"Pump-22", "Valve"}));  // NOT NULL is NULL: "pump" has no Severity
  EXPECT_EQ(names(6), (N{"pump"}));
  EXPECT_EQ(names(7), (N{"Valve", "pump"}));
  EXPECT_EQ(names(8), (N{"Pump-1", "Pump-22"}));
  EXPECT_EQ(names(9), (N{"Pump-1", "Pump-22", "Valve"}));
  EXPECT_EQ(names(10), (N{"Pump-1", "Pump-22"}));
  EXPECT_EQ(names(11), (N{"Valve"}));
  EXPECT_EQ(names(12), (N{"Valve", "pump"}));
}

TEST_F(SubsEvents, InvalidWhereClausesFailTheItemWithDetails) {
  using F = FilterOperator;
  struct Case {
    std::vector<ContentFilterElement> where;
    StatusCode element_status;
    std::vector<StatusCode> operand_status;
  };
  const std::vector<Case> cases = {
      {{element(static_cast<F>(99), {attr("Severity")})}, status::BadFilterOperatorInvalid, {}},
      {{element(F::Cast, {attr("Severity"), lit(NodeId(0, id::Double))})},
       status::BadFilterOperatorUnsupported,
       {}},
      {{element(F::Equals, {attr("Severity")})}, status::BadFilterOperandCountMismatch, {}},
      {{element(F::Not, {elem(0)})}, status::BadFilterOperandInvalid, {status::BadFilterElementInvalid}},
      {{element(F::IsNull, {ExtensionObject::make(AttributeOperand{})})},
       status::BadFilterOperandInvalid,
       {status::BadFilterOperandInvalid}},
      {{element(F::OfType, {lit("not a node id")})},
       status::BadFilterOperandInvalid,
       {status::BadFilterOperandInvalid}},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    auto r = create_items(
        sub, {item_request(NodeId(0, id::Server),
                           params(1, 0, 10, true,
                                  ExtensionObject::make(event_filter({field("Severity")}, cases[i].where))),
                           MonitoringMode::Reporting, kEventNotifier)});
    ASSERT_EQ(r.results.size(), 1U);
    EXPECT_EQ(r.results[0].status_code, status::BadEventFilterInvalid) << "case " << i;
    const auto* result = r.results[0].filter_result.get_if<EventFilterResult>();
    ASSERT_NE(result, nullptr) << "case " << i;
    ASSERT_EQ(result->where_clause_result.element_results.size(), 1U);
    EXPECT_EQ(result->where_clause_result.element_results[0].status_code, cases[i].element_status)
        << "case " << i;
    EXPECT_EQ(
        std::vector<StatusCode>(result->where_clause_result.element_results[0].operand_status_codes.begin(),
                                result->where_clause_result.element_results[0].operand_status_codes.end()),
        cases[i].operand_status)
        << "case " << i;
  }
  EXPECT_EQ(svc->monitored_item_count(), 0U);
}

TEST_F(SubsEvents, InvalidSelectClausesGiveNullFields) {
  SimpleAttributeOperand no_path = field("Severity");
  no_path.browse_path = {};
  const auto r =
      event_item(1, event_filter({field("Severity"), field("Severity", kBaseEventType, kBrowseName),
                                  field("Severity", node("NotAnEventType")), no_path}));
  EXPECT_EQ(r.status_code, status::Good);
  const auto* result = r.filter_result.get_if<EventFilterResult>();
  ASSERT_NE(result, nullptr);
  EXPECT_EQ(result->select_clause_results,
            (Array<StatusCode>{status::Good, status::BadAttributeIdInvalid, status::BadTypeDefinitionInvalid,
                               status::BadBrowseNameInvalid}));
  svc->post_event(NodeId(0, id::Server), event(kBaseEventType, {{"Severity", Variant(std::uint16_t{1})}}));
  const auto got = collect();
  EXPECT_EQ(got.at(1).at(0), (Array<Variant>{Variant(std::uint16_t{1}), Variant{}, Variant{}, Variant{}}));

  EXPECT_EQ(create_items(sub, {item_request(NodeId(0, id::Server),
                                            params(2, 0, 10, true, ExtensionObject::make(event_filter({}))),
                                            MonitoringMode::Reporting, kEventNotifier)})
                .results.at(0)
                .status_code,
            status::BadEventFilterInvalid);
  EXPECT_EQ(create_items(sub, {item_request(NodeId(0, id::Server), params(3, 0, 10),
                                            MonitoringMode::Reporting, kEventNotifier)})
                .results.at(0)
                .status_code,
            status::BadMonitoredItemFilterInvalid);
  EXPECT_EQ(create_items(sub, {item_request(NodeId(0, id::Server),
                                            params(4, 0, 10, true, ExtensionObject::make(DataChangeFilter{})),
                                            MonitoringMode::Reporting, kEventNotifier)})
                .results.at(0)
                .status_code,
            status::BadFilterNotAllowed);
}

class SubsEventOverflow : public SubsEvents {
 protected:
  std::vector<Array<Variant>> run(bool discard_oldest, int count) {
    event_item(1, event_filter({field("EventType"), field("SourceName"), field("Severity")}),
               NodeId(0, id::Server), 2, discard_oldest);
    for (int i = 1; i <= count; ++i) {
      svc->post_event(NodeId(0, id::Server),
                      event(kBaseEventType, {{"SourceName", Variant("e" + std::to_string(i))},
                                             {"Severity", Variant(static_cast<std::uint16_t>(i))}}));
    }
    const auto got = collect();
    return got.contains(1) ? got.at(1) : std::vector<Array<Variant>>{};
  }
};

Array<Variant> overflow_fields() {
  return {Variant(NodeId(0, id::EventQueueOverflowEventType)), Variant("Internal/EventQueueOverflow"),
          Variant(std::uint16_t{1})};
}
Array<Variant> fields_of(int i) {
  return {Variant(kBaseEventType), Variant("e" + std::to_string(i)), Variant(static_cast<std::uint16_t>(i))};
}

TEST_F(SubsEventOverflow, DiscardOldestPutsTheOverflowEventFirst) {
  EXPECT_EQ(run(true, 4), (std::vector<Array<Variant>>{overflow_fields(), fields_of(3), fields_of(4)}));
}

TEST_F(SubsEventOverflow, DiscardNewestPutsTheOverflowEventLast) {
  EXPECT_EQ(run(false, 4), (std::vector<Array<Variant>>{fields_of(1), fields_of(4), overflow_fields()}));
}

TEST_F(SubsEventOverflow, NoOverflowEventWithoutLoss) {
  EXPECT_EQ(run(true, 2), (std::vector<Array<Variant>>{fields_of(1), fields_of(2)}));
}

TEST_F(SubsEvents, DisabledAndSamplingEventItems) {
  const auto item = event_item(1, event_filter({field("SourceName")}));
  SetMonitoringModeRequest req;
  req.subscription_id = sub;
  req.monitored_item_ids = {item.monitored_item_id};
  req.monitoring_mode = MonitoringMode::Disabled;
  svc->set_monitoring_mode(session(), req);
  svc->post_event(NodeId(0, id::Server), event(kBaseEventType, {{"SourceName", Variant("lost")}}));
  req.monitoring_mode = MonitoringMode::Sampling;
  svc->set_monitoring_mode(session(), req);
  svc->post_event(NodeId(0, id::Server), event(kBaseEventType, {{"SourceName", Variant("kept")}}));
  auto got = collect();
  EXPECT_TRUE(got.empty());
  EXPECT_TRUE(is_keep_alive(response(0)));
  req.monitoring_mode = MonitoringMode::Reporting;
  svc->set_monitoring_mode(session(), req);
  got = collect();
  EXPECT_EQ(got.at(1), (std::vector<Array<Variant>>{{Variant("kept")}}));
}

}  // namespace
}  // namespace sf::opcua::subs_test
