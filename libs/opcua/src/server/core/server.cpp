#include "sf/opcua/server/server.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/net/tcp.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

namespace sec = ::sf::opcua::security;

namespace {

// The loop never sleeps longer than this between ticks, so a clock that jumps is caught up.
constexpr auto kMaxTickDelay = std::chrono::milliseconds(1000);

BuildInfo build_info(const ServerConfig& config, const Clock& clock) {
  BuildInfo info;
  info.product_uri = config.identity.product_uri;
  info.manufacturer_name = "smartfactory";
  info.product_name = config.identity.application_name;
  info.software_version = config.software_version;
  info.build_number = config.software_version;
  info.build_date = DateTime::from_system_clock(clock.utc_now());
  return info;
}

// The transport's part of ServerSecurity: the endpoints' policies (and None, for discovery),
// the certificate, client certificate validation, and which policy × mode an OPN may ask for.
Status configure_transport(const std::shared_ptr<const ServerSecurity>& security,
                           ServerTransportConfig& transport) {
  std::vector<std::string> uris;
  for (const auto& endpoint : security->endpoints) {
    if (endpoint.policy_uri != kSecurityPolicyNoneUri &&
        std::find(uris.begin(), uris.end(), endpoint.policy_uri) == uris.end()) {
      uris.push_back(endpoint.policy_uri);
    }
  }
  auto registry = sec::make_registry(uris);
  if (!registry) {
    return registry.error();
  }
  if (!uris.empty() && security->credentials.certificate.empty()) {
    return status_error(
        status::BadConfigurationError,
        "endpoints with security policies need the server's application instance certificate");
  }
  transport.policies = *registry;
  transport.credentials = security->credentials;
  if (security->validator) {
    // OPC 10000-4 §5.5.2: the client learns only BadSecurityChecksFailed; the reason goes to
    // the log (the validator writes it).
    transport.validate_certificate = [validator =
                                          security->validator](const ByteString& certificate) -> Status {
      if (auto st = validator->validate(certificate); !st) {
        return status_error(status::BadSecurityChecksFailed, "the client certificate was rejected");
      }
      return {};
    };
  }
  transport.accept_security = [security](std::string_view policy, MessageSecurityMode mode) -> Status {
    if (policy == kSecurityPolicyNoneUri || security->offers(policy, mode)) {
      return {};  // None is always open for GetEndpoints and FindServers
    }
    return status_error(status::BadSecurityModeRejected,
                        fmt::format("no endpoint with {} and {}", sec::policy_name(policy), to_string(mode)));
  };
  return {};
}

}  // namespace

Server::Server(ServerConfig config, const Clock& clock) : config_(std::move(config)), clock_(clock) {
  if (config_.advertised_host.empty()) {
    config_.advertised_host = net::host_name();
  }
  if (auto st = build_namespace0(space_); !st) {
    // ns0 is generated and tested; failing here is a build defect, not an input problem.
    log::get("opcua")->critical("namespace 0: {}", st.error().message);
  }
  // Namespace 1 is the server's own (OPC 10000-3 §8.2.2): its ApplicationUri.
  space_.add_namespace(config_.identity.application_uri);

  ServerObjectInfo info;
  info.server_uris = {config_.identity.application_uri};
  info.build_info = build_info(config_, clock_);
  info.clock = &clock_;
  info.state = [this] { return state_; };
  info.operation_limits = config_.operations;
  info.max_browse_continuation_points = static_cast<std::uint16_t>(
      std::min<std::size_t>(config_.sessions.max_browse_continuation_points, UINT16_MAX));
  if (auto st = install_server_object_callbacks(space_, std::move(info)); !st) {
    log::get("opcua")->critical("Server object: {}", st.error().message);
  }
  thread_ = std::make_unique<net::LoopThread>();
}

Server::~Server() {
  stop();
}

Status Server::start() {
  if (transport_) {
    return {};
  }
  Status result;
  thread_->run_sync([&] {
    auto transport_config = config_.transport;
    auto security = std::make_shared<const ServerSecurity>(config_.security);
    if (auto st = configure_transport(security, transport_config); !st) {
      result = st;
      return;
    }
    ServerIdentity identity = config_.identity;
    dispatcher_ = std::make_unique<Dispatcher>(space_, clock_, identity, config_.sessions,
                                               config_.subscriptions, config_.operations);
    dispatcher_->set_on_schedule_changed([this] { schedule_tick(); });
    dispatcher_->set_history_database(history_);
    dispatcher_->set_condition_refresh(conditions_);
    dispatcher_->set_security(security);
    auto transport = ServerTransport::start(thread_->loop(), transport_config, *dispatcher_, clock_);
    if (!transport) {
      result = transport.error();
      dispatcher_.reset();
      return;
    }
    transport_ = std::move(*transport);
    port_ = transport_->port();
    state_ = ServerState::Running;
    schedule_tick();
  });
  if (result) {
    log::get("opcua")->info("OPC UA server listening on {} ({}:{})", endpoint_url(), config_.transport.host,
                            port_);
  }
  return result;
}

void Server::stop() {
  if (!thread_) {
    return;
  }
  thread_->run_sync([this] {
    state_ = ServerState::Shutdown;
    if (tick_timer_ != 0) {
      thread_->loop().cancel_timer(tick_timer_);
      tick_timer_ = 0;
    }
    if (dispatcher_) {
      // What clients have not received yet goes out before the connections close.
      dispatcher_->flush_subscriptions();
    }
    if (transport_) {
      transport_->stop();
      transport_.reset();
    }
    dispatcher_.reset();
  });
  thread_.reset();
}

void Server::with_address_space(const std::function<void(AddressSpace&)>& fn) {
  if (!thread_) {
    fn(space_);
    return;
  }
  thread_->run_sync([&] { fn(space_); });
}

net::EventLoop& Server::loop() {
  return thread_->loop();
}

void Server::set_history_database(std::shared_ptr<HistoryDatabase> database) {
  if (!thread_) {
    return;
  }
  thread_->run_sync([&] {
    history_ = std::move(database);
    if (dispatcher_) {
      dispatcher_->set_history_database(history_);
    }
  });
}

void Server::set_condition_refresh(Dispatcher::ConditionSource conditions) {
  if (!thread_) {
    return;
  }
  thread_->run_sync([&] {
    conditions_ = std::move(conditions);
    if (dispatcher_) {
      dispatcher_->set_condition_refresh(conditions_);
    }
  });
}

void Server::raise_event(const NodeId& notifier, SubscriptionService::Event event) {
  if (!thread_) {
    return;
  }
  thread_->loop().post([this, notifier, event = std::move(event)] {
    if (dispatcher_) {
      dispatcher_->raise_event(notifier, event);
    }
  });
}

std::uint16_t Server::port() const {
  return port_;
}

std::string Server::endpoint_url() const {
  return "opc.tcp://" + config_.advertised_host + ":" + std::to_string(port_);
}

template <typename T>
T Server::on_loop(const std::function<T()>& fn) {
  T value{};
  if (thread_) {
    thread_->run_sync([&] { value = fn(); });
  }
  return value;
}

std::size_t Server::session_count() {
  return on_loop<std::size_t>([this] { return dispatcher_ ? dispatcher_->session_count() : 0; });
}

std::size_t Server::subscription_count() {
  return on_loop<std::size_t>(
      [this] { return dispatcher_ ? dispatcher_->subscriptions().subscription_count() : 0; });
}

std::size_t Server::monitored_item_count() {
  return on_loop<std::size_t>(
      [this] { return dispatcher_ ? dispatcher_->subscriptions().monitored_item_count() : 0; });
}

// Keeps one timer armed at the dispatcher's next due time (a monitored item's sampling, a
// publishing cycle, a session timeout).
void Server::schedule_tick() {
  if (!dispatcher_) {
    return;
  }
  const auto now = clock_.now();
  const auto due = std::min(dispatcher_->next_due(), now + kMaxTickDelay);
  if (tick_timer_ != 0 && due >= tick_at_) {
    return;
  }
  if (tick_timer_ != 0) {
    thread_->loop().cancel_timer(tick_timer_);
  }
  tick_at_ = due;
  const auto delay = std::max(Clock::duration::zero(), due - now);
  tick_timer_ = thread_->loop().add_timer(delay, [this] { on_tick(); });
}

void Server::on_tick() {
  tick_timer_ = 0;
  tick_at_ = Clock::time_point::max();
  if (dispatcher_) {
    dispatcher_->tick();
  }
  schedule_tick();
}

}  // namespace sf::opcua::server
