#include "sf/opcua/server/dispatcher.hpp"

#include <algorithm>
#include <type_traits>
#include <utility>

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

// Services that cannot move next_due() earlier: they neither create nor change sessions,
// subscriptions, monitored items or queued Publish requests (they only extend their session's
// lifetime). Rescheduling after them would cost a pass over every monitored item per request.
template <typename T>
constexpr bool kLeavesScheduleAlone =
    std::is_same_v<T, ReadRequest> || std::is_same_v<T, WriteRequest> || std::is_same_v<T, BrowseRequest> ||
    std::is_same_v<T, BrowseNextRequest> || std::is_same_v<T, TranslateBrowsePathsToNodeIdsRequest> ||
    std::is_same_v<T, RegisterNodesRequest> || std::is_same_v<T, UnregisterNodesRequest> ||
    std::is_same_v<T, GetEndpointsRequest> || std::is_same_v<T, FindServersRequest>;

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
  const bool may_reschedule = std::visit(
      [](const auto& typed) { return !kLeavesScheduleAlone<std::decay_t<decltype(typed)>>; }, request);
  std::visit([&](auto& typed) { handle(call, typed); }, request);
  if (may_reschedule && on_schedule_changed_) {
    on_schedule_changed_();
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

template <typename Request, typename Service>
void Dispatcher::with_session(Call& call, const Request& request, Service&& service) {
  auto session = sessions_.find(request.request_header, call.channel_id());
  if (!session) {
    log::get("opcua")->info("{} refused: {}", Request::kTypeName, session.error().message);
    fault(call, request.request_header, status_of(session.error()));
    return;
  }
  auto response = service(**session);
  fill_response_header(response.response_header, request.request_header, clock_);
  call.respond(std::move(response));
}

template <typename Request>
void Dispatcher::handle(Call& call, Request& request) {
  if constexpr (!kIsRequest<Request>) {
    // A response or fault sent to the server: not a service it offers.
    log::get("opcua")->warn("channel {}: {} is not a request", call.channel_id(), Request::kTypeName);
    fault(call, RequestHeader{}, status::BadServiceUnsupported);
  } else if constexpr (std::is_same_v<Request, GetEndpointsRequest>) {
    GetEndpointsResponse response;
    const bool wants_tcp = request.profile_uris.empty() ||
                           std::any_of(request.profile_uris.begin(), request.profile_uris.end(),
                                       [](const String& uri) { return uri == kTransportProfile; });
    if (wants_tcp) {
      response.endpoints = Array<EndpointDescription>(endpoints(request.endpoint_url.view()));
    }
    fill_response_header(response.response_header, request.request_header, clock_);
    call.respond(std::move(response));
  } else if constexpr (std::is_same_v<Request, FindServersRequest>) {
    FindServersResponse response;
    const bool wanted = request.server_uris.empty() ||
                        std::any_of(request.server_uris.begin(), request.server_uris.end(),
                                    [this](const String& uri) { return uri == identity_.application_uri; });
    if (wanted) {
      response.servers = Array<ApplicationDescription>{application_description(request.endpoint_url.view())};
    }
    fill_response_header(response.response_header, request.request_header, clock_);
    call.respond(std::move(response));
  } else if constexpr (std::is_same_v<Request, CreateSessionRequest>) {
    create_session(call, request);
  } else if constexpr (std::is_same_v<Request, ActivateSessionRequest>) {
    activate_session(call, request);
  } else if constexpr (std::is_same_v<Request, CloseSessionRequest>) {
    close_session(call, request);
  } else if constexpr (std::is_same_v<Request, PublishRequest>) {
    publish(call, request);
  } else if constexpr (std::is_same_v<Request, ReadRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return read(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, WriteRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return write(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, BrowseRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return browse(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, BrowseNextRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return browse_next(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, TranslateBrowsePathsToNodeIdsRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return translate_browse_paths(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, RegisterNodesRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return register_nodes(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, UnregisterNodesRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return unregister_nodes(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, CallRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return server::call(space_, request, ctx);
    });
  } else if constexpr (std::is_same_v<Request, CreateSubscriptionRequest>) {
    with_session(call, request, [&](Session& s) {
      return subscriptions_.create_subscription(s.authentication_token, request);
    });
  } else if constexpr (std::is_same_v<Request, ModifySubscriptionRequest>) {
    with_session(call, request, [&](Session& s) {
      return subscriptions_.modify_subscription(s.authentication_token, request);
    });
  } else if constexpr (std::is_same_v<Request, SetPublishingModeRequest>) {
    with_session(call, request, [&](Session& s) {
      return subscriptions_.set_publishing_mode(s.authentication_token, request);
    });
  } else if constexpr (std::is_same_v<Request, DeleteSubscriptionsRequest>) {
    with_session(call, request, [&](Session& s) {
      return subscriptions_.delete_subscriptions(s.authentication_token, request);
    });
  } else if constexpr (std::is_same_v<Request, CreateMonitoredItemsRequest>) {
    with_session(call, request, [&](Session& s) {
      const ServiceContext ctx = context_for(s);
      return subscriptions_.create_monitored_items(
          s.authentication_token, request, [&](const ReadValueId& item, TimestampsToReturn timestamps) {
            return read_attribute(space_, item, timestamps, ctx);
          });
    });
  } else if constexpr (std::is_same_v<Request, ModifyMonitoredItemsRequest>) {
    with_session(call, request, [&](Session& s) {
      return subscriptions_.modify_monitored_items(s.authentication_token, request);
    });
  } else if constexpr (std::is_same_v<Request, SetMonitoringModeRequest>) {
    with_session(call, request, [&](Session& s) {
      return subscriptions_.set_monitoring_mode(s.authentication_token, request);
    });
  } else if constexpr (std::is_same_v<Request, DeleteMonitoredItemsRequest>) {
    with_session(call, request, [&](Session& s) {
      return subscriptions_.delete_monitored_items(s.authentication_token, request);
    });
  } else if constexpr (std::is_same_v<Request, RepublishRequest>) {
    with_session(call, request,
                 [&](Session& s) { return subscriptions_.republish(s.authentication_token, request); });
  } else if constexpr (std::is_same_v<Request, HistoryReadRequest>) {
    with_session(call, request, [&](Session& s) {
      auto ctx = context_for(s);
      return history_read(space_, request, ctx, history_.get());
    });
  } else {
    // OpenSecureChannel/CloseSecureChannel never get here (the transport handles them).
    log::get("opcua")->info("channel {}: {} is not supported", call.channel_id(), Request::kTypeName);
    fault(call, request.request_header, status::BadServiceUnsupported);
  }
}

void Dispatcher::create_session(Call& call, const CreateSessionRequest& request) {
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

void Dispatcher::activate_session(Call& call, const ActivateSessionRequest& request) {
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

void Dispatcher::close_session(Call& call, const CloseSessionRequest& request) {
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

void Dispatcher::publish(Call& call, const PublishRequest& request) {
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
