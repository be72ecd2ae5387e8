// The services the server offers, one row each (the shape of open62541's serviceDescriptions):
// what a request needs before its handler runs and whether it may change what is due next.
// Dispatcher::on_request finds a request's row at compile time; a request without a row is
// answered with BadServiceUnsupported. Adding a service is a row here and its handler, a
// Dispatcher::serve overload (CONTRIBUTING.md, "Adding an OPC UA service").
#pragma once

#include <string_view>
#include <tuple>
#include <type_traits>

#include "sf/opcua/messages.hpp"

namespace sf::opcua::server::detail {

// What the dispatcher does before the handler runs.
enum class Needs {
  nothing,  // no session (discovery): serve(Call&, request)
  own,      // the handler finds or makes its session itself (session set-up, Publish)
  session,  // an activated session of the channel (OPC 10000-4 §5.6.3): serve(SessionScope&, request)
};

// Whether the request may make Dispatcher::next_due() earlier (a new session's expiry, a
// subscription's cycle, a monitored item's sampling, a queued Publish): the server then re-arms
// its timer, which costs a pass over every monitored item. Attribute and view services leave it.
enum class Schedule { unchanged, may_change };

template <typename Request>
struct Service {
  using request_type = Request;
  std::string_view spec;  // where the service is defined
  Needs needs;
  Schedule schedule;
};

// clang-format off
inline constexpr auto kServices = std::make_tuple(
    //      request                                     spec                    needs            schedule
    Service<FindServersRequest>                       {"OPC 10000-4 §5.4.2",  Needs::nothing, Schedule::unchanged},
    Service<GetEndpointsRequest>                      {"OPC 10000-4 §5.4.4",  Needs::nothing, Schedule::unchanged},
    Service<CreateSessionRequest>                     {"OPC 10000-4 §5.6.2",  Needs::own,     Schedule::may_change},
    Service<ActivateSessionRequest>                   {"OPC 10000-4 §5.6.3",  Needs::own,     Schedule::may_change},
    Service<CloseSessionRequest>                      {"OPC 10000-4 §5.6.4",  Needs::own,     Schedule::may_change},
    Service<BrowseRequest>                            {"OPC 10000-4 §5.8.2",  Needs::session, Schedule::unchanged},
    Service<BrowseNextRequest>                        {"OPC 10000-4 §5.8.3",  Needs::session, Schedule::unchanged},
    Service<TranslateBrowsePathsToNodeIdsRequest>     {"OPC 10000-4 §5.8.4",  Needs::session, Schedule::unchanged},
    Service<RegisterNodesRequest>                     {"OPC 10000-4 §5.8.5",  Needs::session, Schedule::unchanged},
    Service<UnregisterNodesRequest>                   {"OPC 10000-4 §5.8.6",  Needs::session, Schedule::unchanged},
    Service<ReadRequest>                              {"OPC 10000-4 §5.10.2", Needs::session, Schedule::unchanged},
    Service<HistoryReadRequest>                       {"OPC 10000-4 §5.10.3", Needs::session, Schedule::may_change},
    Service<WriteRequest>                             {"OPC 10000-4 §5.10.4", Needs::session, Schedule::unchanged},
    Service<CallRequest>                              {"OPC 10000-4 §5.11.2", Needs::session, Schedule::may_change},
    Service<CreateMonitoredItemsRequest>              {"OPC 10000-4 §5.12.2", Needs::session, Schedule::may_change},
    Service<ModifyMonitoredItemsRequest>              {"OPC 10000-4 §5.12.3", Needs::session, Schedule::may_change},
    Service<SetMonitoringModeRequest>                 {"OPC 10000-4 §5.12.4", Needs::session, Schedule::may_change},
    Service<DeleteMonitoredItemsRequest>              {"OPC 10000-4 §5.12.6", Needs::session, Schedule::may_change},
    Service<CreateSubscriptionRequest>                {"OPC 10000-4 §5.13.2", Needs::session, Schedule::may_change},
    Service<ModifySubscriptionRequest>                {"OPC 10000-4 §5.13.3", Needs::session, Schedule::may_change},
    Service<SetPublishingModeRequest>                 {"OPC 10000-4 §5.13.4", Needs::session, Schedule::may_change},
    Service<PublishRequest>                           {"OPC 10000-4 §5.13.5", Needs::own,     Schedule::may_change},
    Service<RepublishRequest>                         {"OPC 10000-4 §5.13.6", Needs::session, Schedule::may_change},
    Service<DeleteSubscriptionsRequest>               {"OPC 10000-4 §5.13.8", Needs::session, Schedule::may_change});
// clang-format on

// Whether the table has a row for Request (at most one: std::get below refuses two).
template <typename Request>
inline constexpr bool kOffered = std::apply(
    [](const auto&... row) {
      return (std::is_same_v<typename std::decay_t<decltype(row)>::request_type, Request> || ...);
    },
    kServices);

// Request's row; only for offered requests.
template <typename Request>
inline constexpr Service<Request> kServiceOf = std::get<Service<Request>>(kServices);

}  // namespace sf::opcua::server::detail
