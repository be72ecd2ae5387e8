#include "sf/opcua/server/dispatcher.hpp"

#include <algorithm>
#include <utility>

#include "service_table.hpp"
#include "session_security.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/opcua/transport/security_policy.hpp"

namespace sf::opcua::server {

namespace {

constexpr std::string_view kTransportProfile =
    "http://opcfoundation.org/UA-Profile/Transport/uatcp-uasc-uabinary";

template <typename T>
constexpr bool kIsRequest = requires(T t) {
  t.request_header;
};

}  // namespace

// One request in flight: where its response goes.
struct Dispatcher::Call {
  const std::shared_ptr<ServerChannel>& channel;
  std::uint32_t request_id;

  [[nodiscard]] std::uint32_t channel_id() const { return channel->info().channel_id; }
  void respond(Message response) const { channel->send_response(request_id, response); }
};

void fill_response_header(ResponseHeader& response, const RequestHeader& request, const Clock& clock,
                          StatusCode result) {
  response.timestamp = DateTime::from_system_clock(clock.utc_now());
  response.request_handle = request.request_handle;
  if (result != StatusCode{}) {
    response.service_result = result;
  }
}

Dispatcher::Dispatcher(AddressSpace& space, const Clock& clock, ServerIdentity identity,
                       SessionLimits session_limits, SubscriptionLimits subscription_limits,
                       OperationLimits operation_limits)
    : space_(space),
      clock_(clock),
      identity_(std::move(identity)),
      operation_limits_(operation_limits),
      sessions_(clock, session_limits),
      subscriptions_(clock, subscription_limits, subscription_callbacks()),
      security_(std::make_shared<const ServerSecurity>()) {}

void Dispatcher::set_security(std::shared_ptr<const ServerSecurity> security) {
  security_ = security ? std::move(security) : std::make_shared<const ServerSecurity>();
}

Dispatcher::~Dispatcher() = default;

SubscriptionCallbacks Dispatcher::subscription_callbacks() {
  SubscriptionCallbacks callbacks;
  callbacks.read = [this](const ReadValueId& item, TimestampsToReturn timestamps) {
    ServiceContext ctx;
    ctx.clock = &clock_;
    return read_attribute(space_, item, timestamps, ctx);
  };
  callbacks.eu_range = [this](const NodeId& node) -> std::optional<Range> {
    const Node* eu = space_.child(node, QualifiedName(0, "EURange"));
    if (eu == nullptr) {
      return std::nullopt;
    }
    auto value = space_.value(eu->node_id);
    if (!value) {
      return std::nullopt;
    }
    const auto* object = value->value.get_if<ExtensionObject>();
    const Range* range = object != nullptr ? object->get_if<Range>() : nullptr;
    return range != nullptr ? std::optional<Range>(*range) : std::nullopt;
  };
  callbacks.is_event_notifier = [this](const NodeId& node) {
    const Node* n = space_.find(node);
    if (n == nullptr) {
      return false;
    }
    if (const auto* object = n->as<ObjectNode>()) {
      return (object->event_notifier & event_notifier::SubscribeToEvents) != 0;
    }
    if (const auto* view = n->as<ViewNode>()) {
      return (view->event_notifier & event_notifier::SubscribeToEvents) != 0;
    }
    return false;
  };
  callbacks.is_subtype = [this](const NodeId& type, const NodeId& base) {
    return space_.is_subtype(type, base);
  };
  return callbacks;
}

ApplicationDescription Dispatcher::application_description(std::string_view endpoint_url) const {
  ApplicationDescription app;
  app.application_uri = identity_.application_uri;
  app.product_uri = identity_.product_uri;
  app.application_name = LocalizedText("en", identity_.application_name);
  app.application_type = ApplicationType::Server;
  app.discovery_urls =
      Array<String>{String(endpoint_url.empty() ? identity_.endpoint_url : std::string(endpoint_url))};
  return app;
}

// OPC 10000-4 §5.4.4: the endpoints use the address the client used to reach us, so that
// clients behind a different host name see URLs they can connect to.
std::vector<EndpointDescription> Dispatcher::endpoints(std::string_view endpoint_url) const {
  const std::string url = endpoint_url.empty() ? identity_.endpoint_url : std::string(endpoint_url);
  std::vector<EndpointDescription> out;
  // OPC 10000-4 §5.4.4: one endpoint per offered policy × mode, with the server certificate and
  // the user token policies of that endpoint.
  for (const auto& offered : security_->endpoints) {
    EndpointDescription endpoint;
    endpoint.endpoint_url = url;
    endpoint.server = application_description(url);
    if (!security_->credentials.certificate.empty()) {
      endpoint.server_certificate = security_->credentials.certificate;
    }
    endpoint.security_mode = offered.mode;
    endpoint.security_policy_uri = offered.policy_uri;
    endpoint.user_identity_tokens = Array<UserTokenPolicy>(user_token_policies(*security_, offered));
    endpoint.transport_profile_uri = std::string(kTransportProfile);
    endpoint.security_level = security_level(offered);
    out.push_back(std::move(endpoint));
  }
  return out;
}

void Dispatcher::on_request(const std::shared_ptr<ServerChannel>& channel, std::uint32_t request_id,
                            Message request) {
  Call call{channel, request_id};
  std::visit([&](const auto& typed) { dispatch(call, typed); }, request);
}

// The request's row of the service table (service_table.hpp) says what to do before its handler.
template <typename Request>
void Dispatcher::dispatch(Call& call, const Request& request) {
  if constexpr (!kIsRequest<Request>) {
    // A response or fault sent to the server: not a service it offers.
    log::get("opcua")->warn("channel {}: {} is not a request", call.channel_id(), Request::kTypeName);
    fault(call, RequestHeader{}, status::BadServiceUnsupported);
  } else if constexpr (!detail::kOffered<Request>) {
    // OpenSecureChannel/CloseSecureChannel never get here (the transport handles them).
    log::get("opcua")->info("channel {}: {} is not supported", call.channel_id(), Request::kTypeName);
    fault(call, request.request_header, status::BadServiceUnsupported);
  } else {
    constexpr auto kRow = detail::kServiceOf<Request>;
    if constexpr (kRow.needs == detail::Needs::session) {
      with_session(call, request);
    } else {
      serve(call, request);
    }
    if (kRow.schedule == detail::Schedule::may_change && on_schedule_changed_) {
      on_schedule_changed_();
    }
  }
}

void Dispatcher::on_channel_closed(std::uint32_t channel_id) {
  // Sessions outlive their channel until they time out, so that a client can re-activate them
  // on a new channel (OPC 10000-4 §6.7).
  log::get("opcua")->debug("channel {} closed; its sessions wait for reactivation", channel_id);
}

void Dispatcher::fault(Call& call, const RequestHeader& header, StatusCode status) {
  ServiceFault fault;
  fill_response_header(fault.response_header, header, clock_, status);
  call.respond(std::move(fault));
}

ServiceContext Dispatcher::context_for(Session& session) {
  ServiceContext ctx;
  ctx.clock = &clock_;
  ctx.limits = operation_limits_;
  ctx.continuations = &session.continuations;
  ctx.user = session.user.get();
  return ctx;
}

// The services that run in an activated session: the session's scope in, the response out.
namespace detail {

// OPC 10000-9 §5.5.2, §5.5.7 (NodeIds.csv).
constexpr std::uint32_t kConditionType = 2782;
constexpr std::uint32_t kConditionRefresh = 3875;

struct SessionScope {
  AddressSpace& space;
  SubscriptionService& subscriptions;
  HistoryDatabase* history = nullptr;
  const Dispatcher::ConditionSource& conditions;
  const Session& session;
  ServiceContext context;
};

// ConditionRefresh (OPC 10000-9 §5.5.7): the method on ConditionType, its one argument checked by
// the Call service already.
bool is_condition_refresh(const CallMethodRequest& m) {
  return m.object_id == NodeId(0, kConditionType) && m.method_id == NodeId(0, kConditionRefresh);
}
StatusCode condition_refresh(SessionScope& s, const CallMethodRequest& m) {
  if (!s.conditions) {
    return status::BadNotImplemented;
  }
  const auto* id = m.input_arguments.empty() ? nullptr : m.input_arguments[0].get_if<std::uint32_t>();
  if (id == nullptr) {
    return status::BadInvalidArgument;
  }
  return s.subscriptions.refresh_conditions(s.session.authentication_token, *id, s.conditions());
}

ReadResponse serve(SessionScope& s, const ReadRequest& r) {
  return read(s.space, r, s.context);
}
WriteResponse serve(SessionScope& s, const WriteRequest& r) {
  return write(s.space, r, s.context);
}
HistoryReadResponse serve(SessionScope& s, const HistoryReadRequest& r) {
  return history_read(s.space, r, s.context, s.history);
}
BrowseResponse serve(SessionScope& s, const BrowseRequest& r) {
  return browse(s.space, r, s.context);
}
BrowseNextResponse serve(SessionScope& s, const BrowseNextRequest& r) {
  return browse_next(s.space, r, s.context);
}
TranslateBrowsePathsToNodeIdsResponse serve(SessionScope& s, const TranslateBrowsePathsToNodeIdsRequest& r) {
  return translate_browse_paths(s.space, r, s.context);
}
RegisterNodesResponse serve(SessionScope& s, const RegisterNodesRequest& r) {
  return register_nodes(s.space, r, s.context);
}
UnregisterNodesResponse serve(SessionScope& s, const UnregisterNodesRequest& r) {
  return unregister_nodes(s.space, r, s.context);
}
CallResponse serve(SessionScope& s, const CallRequest& r) {
  CallResponse response = call(s.space, r, s.context);
  for (std::size_t i = 0; i < response.results.size() && i < r.methods_to_call.size(); ++i) {
    // The node has no callback: its arguments passed when the Call service got that far.
    if (is_condition_refresh(r.methods_to_call[i]) &&
        response.results[i].status_code == status::BadNotImplemented) {
      response.results[i].status_code = condition_refresh(s, r.methods_to_call[i]);
    }
  }
  return response;
}
CreateSubscriptionResponse serve(SessionScope& s, const CreateSubscriptionRequest& r) {
  return s.subscriptions.create_subscription(s.session.authentication_token, r);
}
ModifySubscriptionResponse serve(SessionScope& s, const ModifySubscriptionRequest& r) {
  return s.subscriptions.modify_subscription(s.session.authentication_token, r);
}
SetPublishingModeResponse serve(SessionScope& s, const SetPublishingModeRequest& r) {
  return s.subscriptions.set_publishing_mode(s.session.authentication_token, r);
}
DeleteSubscriptionsResponse serve(SessionScope& s, const DeleteSubscriptionsRequest& r) {
  return s.subscriptions.delete_subscriptions(s.session.authentication_token, r);
}
RepublishResponse serve(SessionScope& s, const RepublishRequest& r) {
  return s.subscriptions.republish(s.session.authentication_token, r);
}
CreateMonitoredItemsResponse serve(SessionScope& s, const CreateMonitoredItemsRequest& r) {
  // The first value of each new item is read with the session's rights.
  return s.subscriptions.create_monitored_items(s.session.authentication_token, r,
                                                [&s](const ReadValueId& item, TimestampsToReturn timestamps) {
                                                  return read_attribute(s.space, item, timestamps, s.context);
                                                });
}
ModifyMonitoredItemsResponse serve(SessionScope& s, const ModifyMonitoredItemsRequest& r) {
  return s.subscriptions.modify_monitored_items(s.session.authentication_token, r);
}
SetMonitoringModeResponse serve(SessionScope& s, const SetMonitoringModeRequest& r) {
  return s.subscriptions.set_monitoring_mode(s.session.authentication_token, r);
}
DeleteMonitoredItemsResponse serve(SessionScope& s, const DeleteMonitoredItemsRequest& r) {
  return s.subscriptions.delete_monitored_items(s.session.authentication_token, r);
}

}  // namespace detail

template <typename Request>
void Dispatcher::with_session(Call& call, const Request& request) {
  auto session = sessions_.find(request.request_header, call.channel_id());
  if (!session) {
    log::get("opcua")->info("{} refused: {}", Request::kTypeName, session.error().message);
    fault(call, request.request_header, status_of(session.error()));
    return;
  }
  detail::SessionScope scope{space_,      subscriptions_, history_.get(),
                             conditions_, **session,      context_for(**session)};
  auto response = detail::serve(scope, request);
  fill_response_header(response.response_header, request.request_header, clock_);
  call.respond(std::move(response));
}

void Dispatcher::serve(Call& call, const GetEndpointsRequest& request) {
  GetEndpointsResponse response;
  const bool wants_tcp =
      request.profile_uris.empty() || std::any_of(request.profile_uris.begin(), request.profile_uris.end(),
                                                  [](const String& uri) { return uri == kTransportProfile; });
  if (wants_tcp) {
    response.endpoints = Array<EndpointDescription>(endpoints(request.endpoint_url.view()));
  }
  fill_response_header(response.response_header, request.request_header, clock_);
  call.respond(std::move(response));
}

void Dispatcher::serve(Call& call, const FindServersRequest& request) {
  FindServersResponse response;
  const bool wanted = request.server_uris.empty() ||
                      std::any_of(request.server_uris.begin(), request.server_uris.end(),
                                  [this](const String& uri) { return uri == identity_.application_uri; });
  if (wanted) {
    response.servers = Array<ApplicationDescription>{application_description(request.endpoint_url.view())};
  }
  fill_response_header(response.response_header, request.request_header, clock_);
  call.respond(std::move(response));
}

void Dispatcher::serve(Call& call, const CreateSessionRequest& request) {
  const ChannelInfo& channel = call.channel->info();
  if (auto st = detail::check_endpoint(*security_, channel); !st) {
    log::get("opcua")->info("CreateSession refused: {}", st.error().message);
    fault(call, request.request_header, status_of(st.error()));
    return;
  }
  auto session = sessions_.create(request, call.channel_id());
  if (!session) {
    fault(call, request.request_header, status_of(session.error()));
    return;
  }
  Session& s = **session;
  CreateSessionResponse response;
  if (auto st = detail::secure_create_session(*security_, channel, request, s, response); !st) {
    log::get("opcua")->warn("CreateSession refused: {}", st.error().message);
    sessions_.remove(s.authentication_token);
    fault(call, request.request_header, status_of(st.error()));
    return;
  }
  response.session_id = s.session_id;
  response.authentication_token = s.authentication_token;
  response.revised_session_timeout = s.timeout_ms;
  response.server_nonce = s.server_nonce;
  response.server_endpoints = Array<EndpointDescription>(endpoints(request.endpoint_url.view()));
  response.max_request_message_size = sessions_.limits().max_request_message_size;
  fill_response_header(response.response_header, request.request_header, clock_);
  call.respond(std::move(response));
}

void Dispatcher::serve(Call& call, const ActivateSessionRequest& request) {
  const ChannelInfo& channel = call.channel->info();
  auto session = sessions_.find_for_activation(request, call.channel_id());
  Result<SessionIdentity> identity = session ? Result<SessionIdentity>(SessionIdentity{}) : session.error();
  if (session) {
    if (auto st = detail::check_endpoint(*security_, channel); !st) {
      identity = st.error();
    } else {
      identity = detail::authenticate_activation(*security_, channel, **session, request, clock_);
    }
  }
  if (identity) {
    auto user = detail::access_for(*security_, space_, *identity);
    session = sessions_.complete_activation(**session, std::move(*identity), request, call.channel_id());
    if (session) {
      (*session)->user = std::move(user);
    }
  } else {
    session = identity.error();
  }
  if (!session) {
    log::get("opcua")->info("ActivateSession refused: {}", session.error().message);
    fault(call, request.request_header, status_of(session.error()));
    return;
  }
  ActivateSessionResponse response;
  response.server_nonce = (*session)->server_nonce;
  fill_response_header(response.response_header, request.request_header, clock_);
  call.respond(std::move(response));
}

void Dispatcher::serve(Call& call, const CloseSessionRequest& request) {
  auto session = sessions_.find_for_close(request.request_header, call.channel_id());
  if (!session) {
    fault(call, request.request_header, status_of(session.error()));
    return;
  }
  const NodeId token = (*session)->authentication_token;
  log::get("opcua")->info("session {} closed by the client", to_string((*session)->session_id));
  subscriptions_.close_session(token, request.delete_subscriptions);
  sessions_.remove(token);
  CloseSessionResponse response;
  fill_response_header(response.response_header, request.request_header, clock_);
  call.respond(std::move(response));
}

void Dispatcher::serve(Call& call, const PublishRequest& request) {
  auto session = sessions_.find(request.request_header, call.channel_id());
  if (!session) {
    fault(call, request.request_header, status_of(session.error()));
    return;
  }
  // The response may come much later (next publishing cycle): it goes to the channel the
  // request came on, if that is still open; otherwise the client republishes what it missed.
  std::weak_ptr<ServerChannel> channel = call.channel;
  const std::uint32_t request_id = call.request_id;
  subscriptions_.publish((*session)->authentication_token, request, [channel, request_id](Message response) {
    if (auto open = channel.lock(); open && open->is_open()) {
      open->send_response(request_id, response);
    }
  });
}

void Dispatcher::tick() {
  for (const NodeId& token : sessions_.expire()) {
    subscriptions_.close_session(token, true);
  }
  subscriptions_.tick();
}

Clock::time_point Dispatcher::next_due() const {
  return std::min(sessions_.next_expiry(), subscriptions_.next_due());
}

void Dispatcher::raise_event(const NodeId& notifier, const SubscriptionService::Event& event) {
  subscriptions_.post_event(notifier, event);
  if (on_schedule_changed_) {
    on_schedule_changed_();
  }
}

}  // namespace sf::opcua::server
