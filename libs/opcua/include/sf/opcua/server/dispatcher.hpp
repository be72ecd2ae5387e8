// The heart of the server: takes decoded service requests from the transport, checks their
// session (OPC 10000-4 §5.6) and runs the service over the address space and the subscriptions
// engine. No sockets and no threads of its own: the Server drives it on its loop thread, tests
// and the fuzz target drive it directly with a fake ServerChannel and a ManualClock.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/opcua/server/address_space.hpp"
#include "sf/opcua/server/history.hpp"
#include "sf/opcua/server/security.hpp"
#include "sf/opcua/server/services.hpp"
#include "sf/opcua/server/session.hpp"
#include "sf/opcua/server/subscriptions.hpp"
#include "sf/opcua/transport/server_transport.hpp"

namespace sf::opcua::server {

// Who the server says it is (OPC 10000-4 §7.2 ApplicationDescription) and how it is reached.
struct ServerIdentity {
  std::string application_uri = "urn:smartfactory:opcua:server";
  std::string product_uri = "urn:smartfactory";
  std::string application_name = "smartfactory OPC UA server";
  // Used in GetEndpoints/FindServers when the request names no endpoint URL.
  std::string endpoint_url = "opc.tcp://localhost:4840";
};

class Dispatcher final : public ServiceHandler {
 public:
  Dispatcher(AddressSpace& space, const Clock& clock, ServerIdentity identity, SessionLimits session_limits,
             SubscriptionLimits subscription_limits, OperationLimits operation_limits);
  ~Dispatcher() override;
  Dispatcher(const Dispatcher&) = delete;
  Dispatcher& operator=(const Dispatcher&) = delete;

  void on_request(const std::shared_ptr<ServerChannel>& channel, std::uint32_t request_id,
                  Message request) override;
  void on_channel_closed(std::uint32_t channel_id) override;
  [[nodiscard]] bool holds_session(std::uint32_t channel_id) const override {
    return sessions_.has_activated_session(channel_id);
  }

  // Before the server stops: sends the notifications the subscriptions hold (see
  // SubscriptionService::flush).
  void flush_subscriptions() { subscriptions_.flush(); }
  // Expires sessions, samples monitored items, runs publishing cycles. Call at next_due().
  void tick();
  [[nodiscard]] Clock::time_point next_due() const;

  // Called after every request that may have moved next_due() earlier (the service table's
  // Schedule::may_change rows).
  void set_on_schedule_changed(std::function<void()> callback) { on_schedule_changed_ = std::move(callback); }
  // Endpoints, certificate, client certificate validation, users and roles (OPC 10000-2 §4); nullptr
  // or never called: SecurityPolicy None with unrestricted anonymous users.
  void set_security(std::shared_ptr<const ServerSecurity> security);
  // Where HistoryRead finds values (nullptr: HistoryRead answers BadHistoryOperationUnsupported).
  void set_history_database(std::shared_ptr<HistoryDatabase> database) { history_ = std::move(database); }
  // The retained conditions a ConditionRefresh (OPC 10000-9 §5.5.7) reports, as events; never
  // set: the method answers BadNotImplemented. Called on the loop thread.
  using ConditionSource = std::function<std::vector<SubscriptionService::Event>()>;
  void set_condition_refresh(ConditionSource conditions) { conditions_ = std::move(conditions); }

  // An event raised by `source` (OPC 10000-5 §6.4.2 BaseEventType fields), reported to event
  // items on `notifier` and on the Server object.
  void raise_event(const NodeId& notifier, const SubscriptionService::Event& event);

  [[nodiscard]] std::vector<EndpointDescription> endpoints(std::string_view endpoint_url) const;
  [[nodiscard]] ApplicationDescription application_description(std::string_view endpoint_url) const;
  [[nodiscard]] std::size_t session_count() const { return sessions_.size(); }
  [[nodiscard]] const SubscriptionService& subscriptions() const { return subscriptions_; }
  [[nodiscard]] const OperationLimits& operation_limits() const { return operation_limits_; }

 private:
  struct Call;
  // By the request's row of the service table (src/server/core/service_table.hpp).
  template <typename Request>
  void dispatch(Call& call, const Request& request);
  // Finds the request's session, runs the service in it and responds (or faults).
  template <typename Request>
  void with_session(Call& call, const Request& request);

  // The handlers of the services that need no session or find their own.
  void serve(Call& call, const FindServersRequest& request);
  void serve(Call& call, const GetEndpointsRequest& request);
  void serve(Call& call, const CreateSessionRequest& request);
  void serve(Call& call, const ActivateSessionRequest& request);
  void serve(Call& call, const CloseSessionRequest& request);
  void serve(Call& call, const PublishRequest& request);
  void fault(Call& call, const RequestHeader& header, StatusCode status);
  ServiceContext context_for(Session& session);
  SubscriptionCallbacks subscription_callbacks();

  AddressSpace& space_;
  const Clock& clock_;
  ServerIdentity identity_;
  OperationLimits operation_limits_;
  SessionManager sessions_;
  SubscriptionService subscriptions_;
  std::function<void()> on_schedule_changed_;
  std::shared_ptr<HistoryDatabase> history_;
  ConditionSource conditions_;
  std::shared_ptr<const ServerSecurity> security_;
};

// Fills the ResponseHeader fields every response carries (OPC 10000-4 §7.33).
void fill_response_header(ResponseHeader& response, const RequestHeader& request, const Clock& clock,
                          StatusCode result = StatusCode{});

}  // namespace sf::opcua::server
