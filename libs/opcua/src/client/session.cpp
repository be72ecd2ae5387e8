// Opening a session: secure channel, CreateSession and ActivateSession (OPC 10000-4 §5.6.2,
// §5.6.3) with an anonymous identity token, and reactivating the session on a new channel
// (§6.7); plus the request plumbing shared by all services (RequestHeader, §7.33).
#include <algorithm>
#include <random>

#include "client_impl.hpp"

namespace sf::opcua {

namespace client_detail {

bool is_transport_error(StatusCode code) {
  const std::uint32_t c = code.code();
  return c == status::BadTimeout.code() || c == status::BadRequestTimeout.code() ||
         c == status::BadSecureChannelClosed.code() || c == status::BadConnectionClosed.code() ||
         c == status::BadNotConnected.code() || c == status::BadServerNotConnected.code() ||
         c == status::BadCommunicationError.code() || c == status::BadSecureChannelIdInvalid.code() ||
         c == status::BadRequestInterrupted.code();
}

bool is_session_error(StatusCode code) {
  const std::uint32_t c = code.code();
  return c == status::BadSessionIdInvalid.code() || c == status::BadSessionClosed.code() ||
         c == status::BadSessionNotActivated.code();
}

}  // namespace client_detail

namespace {

ByteString random_nonce() {
  std::random_device device;
  Bytes bytes(32);
  for (auto& b : bytes) {
    b = static_cast<std::uint8_t>(device() & 0xFFU);
  }
  return ByteString(std::move(bytes));
}

// The policy id of an anonymous UserTokenPolicy (OPC 10000-4 §7.41), preferring the endpoint
// that matches our security (None); "" if the server offers none.
std::string anonymous_policy_id(const Array<EndpointDescription>& endpoints) {
  const EndpointDescription* best = nullptr;
  std::string id;
  for (const auto& endpoint : endpoints) {
    for (const auto& policy : endpoint.user_identity_tokens) {
      if (policy.token_type != UserTokenType::Anonymous) {
        continue;
      }
      const bool matches = endpoint.security_mode == MessageSecurityMode::None &&
                           endpoint.security_policy_uri == kSecurityPolicyNoneUri;
      if (best == nullptr || matches) {
        best = &endpoint;
        id = policy.policy_id.str();
      }
      if (matches) {
        return id;
      }
    }
  }
  return id;
}

}  // namespace

Client::Impl::Impl(net::EventLoop& event_loop, ClientConfig client_config)
    : loop(event_loop), config(std::move(client_config)), logger(log::get("opcua")) {
  publish_target = std::max<std::size_t>(1, config.publish_requests);
  backoff = config.reconnect_min;
}

RequestHeader Client::Impl::make_header(std::chrono::milliseconds timeout) {
  RequestHeader header;
  if (session) {
    header.authentication_token = session->authentication_token;
  }
  header.timestamp = DateTime::from_system_clock(loop.clock().utc_now());
  header.request_handle = next_request_handle++;
  if (next_request_handle == 0) {
    next_request_handle = 1;
  }
  header.timeout_hint = static_cast<std::uint32_t>(std::clamp<std::chrono::milliseconds::rep>(
      timeout.count(), 0, std::chrono::milliseconds::rep{UINT32_MAX}));
  return header;
}

void Client::Impl::post(std::function<void()> fn) {
  loop.post([weak = weak_from_this(), fn = std::move(fn)]() {
    if (auto self = weak.lock(); self && !self->shut_down) {
      fn();
    }
  });
}

std::optional<Error> Client::Impl::check_connected(std::string_view what) const {
  if (state != ClientState::Connected || !channel || !session || !session->activated) {
    return status_error(status::BadNotConnected,
                        std::string(what) + ": client is " + std::string(to_string(state)));
  }
  return std::nullopt;
}

void Client::Impl::set_state(ClientState next, const Status& reason) {
  if (next == state) {
    return;
  }
  state = next;
  state_mirror.store(next);
  if (reason) {
    logger->info("opcua client {}: {}", config.endpoint_url, to_string(next));
  } else {
    logger->info("opcua client {}: {} ({})", config.endpoint_url, to_string(next), reason.error().message);
  }
  if (on_state) {
    on_state(next, reason);
  }
}

void Client::Impl::connect(std::function<void(Status)> done) {
  if (state != ClientState::Disconnected || disconnecting) {
    post([done = std::move(done), s = state]() {
      done(status_error(status::BadInvalidState, "connect: client is " + std::string(to_string(s))));
    });
    return;
  }
  connect_done = std::move(done);
  backoff = config.reconnect_min;
  set_state(ClientState::Connecting, {});
  open_channel();
}

void Client::Impl::open_channel() {
  const std::uint64_t generation = ++channel_generation;
  if (plain()) {
    endpoint.reset();
    open_transport(generation, transport_config());
    return;
  }
  discover_endpoint(generation, [this, generation](Result<EndpointDescription> found) {
    if (!found) {
      logger->warn("opcua client {}: no usable endpoint: {}", config.endpoint_url, found.error().message);
      lose_channel(generation, found.error());
      return;
    }
    endpoint = std::move(*found);
    const std::string_view policy = endpoint->security_policy_uri.view();
    logger->info("opcua client {}: endpoint {} {}", config.endpoint_url, policy.substr(policy.rfind('#') + 1),
                 to_string(endpoint->security_mode));
    open_transport(generation, transport_config());
  });
}

void Client::Impl::open_transport(std::uint64_t generation, ClientTransportConfig transport) {
  ClientChannel::open(loop, std::move(transport),
                      [weak = weak_from_this(), generation](Result<std::shared_ptr<ClientChannel>> opened) {
                        auto self = weak.lock();
                        if (!self || self->shut_down) {
                          if (opened) {
                            (*opened)->close();
                          }
                          return;
                        }
                        self->on_channel_open(generation, std::move(opened));
                      });
}

void Client::Impl::on_channel_open(std::uint64_t generation, Result<std::shared_ptr<ClientChannel>> opened) {
  if (generation != channel_generation) {
    if (opened) {
      (*opened)->close();
    }
    return;
  }
  if (!opened) {
    logger->warn("opcua client {}: cannot open a secure channel: {}", config.endpoint_url,
                 opened.error().message);
    lose_channel(generation, opened.error());
    return;
  }
  channel = std::move(*opened);
  channel->set_on_closed([weak = weak_from_this(), generation](const Status& status) {
    auto self = weak.lock();
    if (!self || self->shut_down) {
      return;
    }
    self->lose_channel(generation,
                       status ? status_error(status::BadConnectionClosed, "secure channel closed by server")
                              : status.error());
  });
  if (session) {
    activate_session(true);
  } else {
    create_session();
  }
}

void Client::Impl::create_session() {
  CreateSessionRequest request;
  request.client_description.application_uri = config.application_uri;
  request.client_description.product_uri = "urn:smartfactory";
  request.client_description.application_name = LocalizedText(String(), config.application_name);
  request.client_description.application_type = ApplicationType::Client;
  request.endpoint_url = config.endpoint_url;
  request.session_name = config.session_name;
  request.client_nonce = random_nonce();
  request.requested_session_timeout = config.session_timeout_ms;
  request.max_response_message_size = config.limits.max_message_size;
  secure_create_request(request);
  const std::uint64_t generation = channel_generation;
  send(std::move(request), [this, generation](Result<CreateSessionResponse> response) {
    if (generation != channel_generation) {
      return;
    }
    if (!response) {
      logger->warn("opcua client {}: CreateSession failed: {}", config.endpoint_url,
                   response.error().message);
      lose_channel(generation, response.error());
      return;
    }
    if (auto st = check_create_response(*response); !st) {
      logger->warn("opcua client {}: CreateSession: {}", config.endpoint_url, st.error().message);
      lose_channel(generation, st.error());
      return;
    }
    Session created;
    created.session_id = response->session_id;
    created.authentication_token = response->authentication_token;
    created.revised_timeout_ms = response->revised_session_timeout;
    created.server_certificate = response->server_certificate;
    created.server_nonce = response->server_nonce;
    created.anonymous_policy_id = anonymous_policy_id(response->server_endpoints);
    if (created.anonymous_policy_id.empty()) {
      logger->warn("opcua client {}: the server lists no anonymous UserTokenPolicy; trying \"anonymous\"",
                   config.endpoint_url);
      created.anonymous_policy_id = "anonymous";
    }
    session = std::move(created);
    ++session_epoch;
    activate_session(false);
  });
}

void Client::Impl::activate_session(bool reactivating) {
  ActivateSessionRequest request;
  const std::uint64_t generation = channel_generation;
  if (auto st = fill_activation(request); !st) {
    logger->warn("opcua client {}: ActivateSession: {}", config.endpoint_url, st.error().message);
    post([this, generation, error = st.error()]() { lose_channel(generation, error); });
    return;
  }
  send(std::move(request), [this, generation, reactivating](Result<ActivateSessionResponse> response) {
    if (generation != channel_generation) {
      return;
    }
    if (!response) {
      const StatusCode code = status_of(response.error());
      if (reactivating && !client_detail::is_transport_error(code)) {
        // OPC 10000-4 §6.7: the session is gone (BadSessionIdInvalid, ...): start over with a
        // new session and re-create the subscriptions.
        logger->info("opcua client {}: session not reactivated ({}); creating a new one", config.endpoint_url,
                     response.error().message);
        forget_session();
        create_session();
        return;
      }
      logger->warn("opcua client {}: ActivateSession failed: {}", config.endpoint_url,
                   response.error().message);
      lose_channel(generation, response.error());
      return;
    }
    session->activated = true;
    session->server_nonce = response->server_nonce;
    on_session_active(reactivating);
  });
}

void Client::Impl::on_session_active(bool reactivated) {
  backoff = config.reconnect_min;
  start_keep_alive();
  if (state == ClientState::Connecting) {
    finish_connect();
    return;
  }
  if (reactivated) {
    republish_missing();
    set_state(ClientState::Connected, {});
    pump_publish();
    return;
  }
  publish_target = std::max<std::size_t>(1, config.publish_requests);  // a new session, new limits
  const std::uint64_t generation = channel_generation;
  recreate_subscriptions([this, generation]() {
    if (generation != channel_generation) {
      return;
    }
    set_state(ClientState::Connected, {});
    pump_publish();
  });
}

void Client::Impl::finish_connect() {
  set_state(ClientState::Connected, {});
  if (auto done = std::exchange(connect_done, nullptr)) {
    done({});
  }
}

}  // namespace sf::opcua
