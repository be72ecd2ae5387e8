// ServerTransport: one SecureChannel per accepted TCP connection (OPC 10000-6 §7.1, §6.7).
#include "sf/opcua/transport/server_transport.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "channel_timer.hpp"
#include "sf/core/log.hpp"
#include "sf/net/tcp.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/opcua/transport/secure_channel.hpp"
#include "transport/transport_log.hpp"

namespace sf::opcua {
namespace {

using detail::logger;

class ServerConnection;

// "127.0.0.1:53124" → "127.0.0.1", "[::1]:4840" → "[::1]".
std::string source_address(const std::string& peer) {
  return peer.substr(0, peer.rfind(':'));
}

}  // namespace

struct ServerTransport::Impl : std::enable_shared_from_this<ServerTransport::Impl> {
  Impl(net::EventLoop& l, ServerTransportConfig c, ServiceHandler& h, const Clock& k)
      : loop(l), config(std::move(c)), handler(h), clock(k) {}

  net::EventLoop& loop;
  ServerTransportConfig config;
  ServiceHandler& handler;
  const Clock& clock;
  std::unique_ptr<net::TcpListener> listener;
  std::map<std::uint64_t, std::shared_ptr<ServerConnection>> connections;
  std::uint64_t next_key = 1;
  std::uint32_t next_channel_id = 1;
  bool stopped = false;

  void accept(std::shared_ptr<net::TcpConnection> tcp);
  bool make_room(const std::string& address);
  bool evict_one(const std::string* address);
  void refuse(const std::shared_ptr<net::TcpConnection>& tcp, std::string reason);
  std::uint32_t allocate_channel_id();
  void remove(std::uint64_t key);
};

namespace {

class ServerConnection final : public ServerChannel, public std::enable_shared_from_this<ServerConnection> {
 public:
  ServerConnection(const std::shared_ptr<ServerTransport::Impl>& owner, std::uint64_t key,
                   std::shared_ptr<net::TcpConnection> tcp, SecureChannelConfig config)
      : owner_(owner),
        loop_(owner->loop),
        handler_(owner->handler),
        clock_(owner->clock),
        key_(key),
        tcp_(std::move(tcp)),
        channel_(std::move(config), owner->clock) {
    info_.peer = tcp_->peer();
    address_ = source_address(info_.peer);
  }

  ~ServerConnection() override { cancel_timers(); }
  ServerConnection(const ServerConnection&) = delete;
  ServerConnection& operator=(const ServerConnection&) = delete;

  void start(std::chrono::milliseconds hello_timeout) {
    std::weak_ptr<ServerConnection> weak = weak_from_this();
    tcp_->set_on_close([weak](const Status& status) {
      if (auto self = weak.lock()) {
        self->on_tcp_closed(status);
      }
    });
    tcp_->set_on_data([weak](ByteSpan bytes) {
      if (auto self = weak.lock()) {
        self->channel_.receive(bytes);
        self->pump();
      }
    });
    // §7.1.2: a connection that does not open a secure channel in time is dropped.
    hello_timer_ = loop_.add_timer(hello_timeout, [weak] {
      if (auto self = weak.lock()) {
        self->hello_timer_ = 0;
        if (!self->channel_.is_open()) {
          self->channel_.fail(status::BadTimeout, "no HEL/OPN in time");
          self->pump();
        }
      }
    });
  }

  [[nodiscard]] const ChannelInfo& info() const override { return info_; }

  void send_response(std::uint32_t request_id, const Message& response) override {
    if (!channel_.is_open()) {
      logger()->debug("channel {}: response {} dropped, channel closed", info_.channel_id, request_id);
      return;
    }
    (void)channel_.send_response(request_id, response);
    pump();
  }

  void close() override {
    channel_.close();
    pump();
  }

  [[nodiscard]] bool is_open() const override { return channel_.is_open() && !finished_; }
  // A secure channel was opened (OPN answered) on this connection.
  [[nodiscard]] bool opened() const { return opened_; }
  [[nodiscard]] const std::string& address() const { return address_; }

  // Gives the connection's place to a new one (Part 6 §7.1.5: ERR, then close).
  void evict() {
    channel_.fail(status::BadTcpNotEnoughResources,
                  opened_ ? "the channel was closed for a new connection: no session uses it"
                          : "the connection was closed for a new one: no secure channel opened yet");
    pump();
  }

  // stop(): close without telling the owner (it is clearing its map).
  void shut_down() {
    detached_ = true;
    channel_.close();
    pump();
  }

 private:
  // Moves output to the socket and acts on events until there is nothing left; safe to
  // re-enter from a handler callback.
  void pump() {
    if (pumping_) {
      return;  // the outer call loops until both queues are empty
    }
    auto self = shared_from_this();
    pumping_ = true;
    while (channel_.has_output() || channel_.has_events()) {
      if (channel_.has_output()) {
        tcp_->send(channel_.take_output());
      }
      for (auto& event : channel_.take_events()) {
        handle(event);
      }
    }
    pumping_ = false;
    arm_timer();
  }

  void handle(ChannelEvent& event) {
    switch (event.kind) {
      case ChannelEvent::Kind::Opened:
        info_.channel_id = channel_.channel_id();
        info_.endpoint_url = channel_.endpoint_url();
        info_.security_policy_uri = channel_.security_policy_uri();
        info_.security_mode = channel_.security_mode();
        info_.client_certificate = channel_.peer_certificate();
        opened_ = true;
        if (hello_timer_ != 0) {
          loop_.cancel_timer(hello_timer_);
          hello_timer_ = 0;
        }
        logger()->info("secure channel {} opened from {} for '{}'", info_.channel_id, info_.peer,
                       info_.endpoint_url);
        break;
      case ChannelEvent::Kind::Renewed:
        break;
      case ChannelEvent::Kind::ServiceMessage:
        if (!detached_) {
          handler_.on_request(shared_from_this(), event.request_id, std::move(*event.message));
        }
        break;
      case ChannelEvent::Kind::Undecodable: {
        // Part 4 §7.30: unknown services → BadServiceUnsupported, the rest BadDecodingError,
        // with the requestHandle when it could be read.
        ServiceFault fault;
        fault.response_header.timestamp = DateTime::from_system_clock(clock_.utc_now());
        fault.response_header.request_handle = event.request_handle;
        fault.response_header.service_result = event.status;
        (void)channel_.send_response(event.request_id, fault);
        break;
      }
      case ChannelEvent::Kind::Aborted:
        break;  // the request was never delivered; nothing to answer
      case ChannelEvent::Kind::Closed:
        finish(event.status.is_good() ? std::string("closed") : std::string(event.status.name()));
        break;
    }
  }

  void finish(const std::string& why) {
    if (finished_) {
      return;
    }
    finished_ = true;
    cancel_timers();
    if (channel_.has_output()) {
      tcp_->send(channel_.take_output());
    }
    tcp_->close();  // flushes an ERR before the FIN
    logger()->debug("connection {} (channel {}) closed: {}", info_.peer, info_.channel_id, why);
    notify_owner();
  }

  void on_tcp_closed(const Status& status) {
    if (finished_) {
      return;
    }
    finished_ = true;
    cancel_timers();
    logger()->debug("connection {} (channel {}) lost: {}", info_.peer, info_.channel_id,
                    status.ok() ? std::string("peer closed") : status.error().message);
    notify_owner();
  }

  void notify_owner() {
    if (detached_) {
      return;
    }
    detached_ = true;
    auto self = shared_from_this();
    if (auto owner = owner_.lock()) {
      owner->remove(key_);
    }
    if (opened_) {
      handler_.on_channel_closed(info_.channel_id);
    }
  }

  void arm_timer() {
    detail::arm_channel_timer(loop_, clock_, tick_timer_, finished_ ? std::nullopt : channel_.next_deadline(),
                              [weak = weak_from_this()] {
                                if (auto self = weak.lock()) {
                                  self->on_channel_timer();
                                }
                              });
  }

  void on_channel_timer() {
    tick_timer_ = 0;
    channel_.on_timer();
    pump();
  }
  void cancel_timers() {
    if (hello_timer_ != 0) {
      loop_.cancel_timer(hello_timer_);
      hello_timer_ = 0;
    }
    if (tick_timer_ != 0) {
      loop_.cancel_timer(tick_timer_);
      tick_timer_ = 0;
    }
  }

  std::weak_ptr<ServerTransport::Impl> owner_;
  net::EventLoop& loop_;
  ServiceHandler& handler_;
  const Clock& clock_;
  std::uint64_t key_;
  std::shared_ptr<net::TcpConnection> tcp_;
  SecureChannel channel_;
  ChannelInfo info_;
  std::string address_;
  net::EventLoop::TimerId hello_timer_ = 0;
  net::EventLoop::TimerId tick_timer_ = 0;
  bool pumping_ = false;
  bool opened_ = false;
  bool finished_ = false;
  bool detached_ = false;
};

}  // namespace

void ServerTransport::Impl::accept(std::shared_ptr<net::TcpConnection> tcp) {
  if (stopped) {
    tcp->abort();
    return;
  }
  if (!make_room(source_address(tcp->peer()))) {
    refuse(tcp,
           fmt::format("every one of the server's secure channels ({} in all, {} per address) has a session",
                       config.max_channels, config.max_channels_per_address));
    return;
  }
  SecureChannelConfig sc;
  sc.role = ChannelRole::Server;
  sc.limits = config.limits;
  sc.decode_limits = config.decode_limits;
  sc.policies = config.policies;
  sc.credentials = config.credentials;
  sc.validate_certificate = config.validate_certificate;
  sc.accept_security = config.accept_security;
  sc.channel_id = allocate_channel_id();
  sc.max_token_lifetime_ms = config.max_token_lifetime_ms;
  sc.min_token_lifetime_ms = config.min_token_lifetime_ms;
  const std::uint64_t key = next_key++;
  auto conn = std::make_shared<ServerConnection>(shared_from_this(), key, std::move(tcp), std::move(sc));
  connections.emplace(key, conn);
  conn->start(config.hello_timeout);
}

// A place for a new connection from `address` within both limits, evicting where needed.
bool ServerTransport::Impl::make_room(const std::string& address) {
  if (config.max_channels_per_address != 0) {
    const auto from_address = static_cast<std::size_t>(
        std::count_if(connections.begin(), connections.end(),
                      [&](const auto& entry) { return entry.second->address() == address; }));
    if (from_address >= config.max_channels_per_address && !evict_one(&address)) {
      return false;
    }
  }
  return connections.size() < config.max_channels || evict_one(nullptr);
}

// Evicts the oldest connection (of `address`, or of any) without a secure channel, else the
// oldest channel without an activated session, so that neither silent connections nor channels
// opened and left idle starve clients that log in. False when every channel holds a session.
bool ServerTransport::Impl::evict_one(const std::string* address) {
  std::shared_ptr<ServerConnection> victim;
  for (const bool opened : {false, true}) {
    for (const auto& [key, conn] : connections) {  // keys grow with age: oldest first
      if ((address == nullptr || conn->address() == *address) && conn->opened() == opened &&
          (!opened || !handler.holds_session(conn->info().channel_id))) {
        victim = conn;
        break;
      }
    }
    if (victim) {
      break;
    }
  }
  if (!victim) {
    return false;
  }
  logger()->debug("connection {} (channel {}) evicted for a new connection", victim->info().peer,
                  victim->info().channel_id);
  victim->evict();  // removes itself from `connections`
  return true;
}

// §7.1.5: refuse with ERR; the connection lives until its close completes.
void ServerTransport::Impl::refuse(const std::shared_ptr<net::TcpConnection>& tcp, std::string reason) {
  logger()->warn("connection from {} rejected: {}", tcp->peer(), reason);
  tcp->set_on_close([tcp](const Status&) {});
  tcp->send(encode_error(ErrorMessage{status::BadTcpNotEnoughResources, std::move(reason)}));
  tcp->close();
}

std::uint32_t ServerTransport::Impl::allocate_channel_id() {
  // Unique among live channels; the start value differs per run (§6.7.2.2 asks for ids that
  // are unlikely to repeat after a restart).
  for (;;) {
    const std::uint32_t id = next_channel_id++;
    if (id == 0) {
      continue;
    }
    bool used = false;
    for (const auto& [key, conn] : connections) {
      used = used || conn->info().channel_id == id;
    }
    if (!used) {
      return id;
    }
  }
}

void ServerTransport::Impl::remove(std::uint64_t key) {
  connections.erase(key);
}

Result<std::unique_ptr<ServerTransport>> ServerTransport::start(net::EventLoop& loop,
                                                                ServerTransportConfig config,
                                                                ServiceHandler& handler, const Clock& clock) {
  auto impl = std::make_shared<Impl>(loop, std::move(config), handler, clock);
  const auto seed =
      std::chrono::duration_cast<std::chrono::seconds>(clock.utc_now().time_since_epoch()).count();
  impl->next_channel_id = static_cast<std::uint32_t>(seed & 0xFFFFU) << 16U | 1U;
  Impl* raw = impl.get();
  auto listener = net::TcpListener::listen(
      loop, impl->config.host, impl->config.port,
      [raw](std::shared_ptr<net::TcpConnection> tcp) { raw->accept(std::move(tcp)); });
  if (!listener.ok()) {
    return status_error(status::BadResourceUnavailable, listener.error().message);
  }
  impl->listener = std::move(*listener);
  logger()->info("OPC UA TCP listening on {}:{}", impl->config.host, impl->listener->port());
  return std::unique_ptr<ServerTransport>(new ServerTransport(std::move(impl)));
}

ServerTransport::ServerTransport(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

ServerTransport::~ServerTransport() {
  stop();
}

std::uint16_t ServerTransport::port() const {
  return impl_->listener ? impl_->listener->port() : 0;
}

std::size_t ServerTransport::channel_count() const {
  return impl_->connections.size();
}

void ServerTransport::stop() {
  if (impl_->stopped) {
    return;
  }
  impl_->stopped = true;
  impl_->listener.reset();
  auto connections = std::move(impl_->connections);
  impl_->connections.clear();
  for (auto& [key, conn] : connections) {
    const bool was_open = conn->is_open();
    const std::uint32_t id = conn->info().channel_id;
    conn->shut_down();
    if (was_open) {
      impl_->handler.on_channel_closed(id);
    }
  }
}

}  // namespace sf::opcua
