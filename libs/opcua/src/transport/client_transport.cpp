// ClientChannel: a SecureChannel over one TCP connection, with request bookkeeping.
#include "sf/opcua/transport/client_transport.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "channel_timer.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/status_codes.hpp"
#include "transport/transport_log.hpp"

namespace sf::opcua {
namespace {

using detail::logger;

constexpr std::uint16_t kDefaultPort = 4840;

bool starts_with_ci(std::string_view text, std::string_view prefix) {
  return text.size() >= prefix.size() &&
         std::equal(prefix.begin(), prefix.end(), text.begin(), [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
         });
}

SecureChannelConfig channel_config(const ClientTransportConfig& c) {
  SecureChannelConfig sc;
  sc.role = ChannelRole::Client;
  sc.limits = c.limits;
  sc.decode_limits = c.decode_limits;
  sc.policies = c.policies;
  sc.credentials = c.credentials;
  sc.validate_certificate = c.validate_certificate;
  sc.endpoint_url = c.endpoint_url;
  sc.security_policy_uri = c.security_policy_uri;
  sc.security_mode = c.security_mode;
  sc.requested_lifetime_ms = c.requested_lifetime_ms;
  sc.server_certificate = c.server_certificate;
  return sc;
}

}  // namespace

Result<std::pair<std::string, std::uint16_t>> parse_endpoint_url(std::string_view url) {
  constexpr std::string_view kScheme = "opc.tcp://";
  const auto invalid = [url](std::string_view why) {
    return status_error(status::BadTcpEndpointUrlInvalid, fmt::format("endpoint URL '{}': {}", url, why));
  };
  if (!starts_with_ci(url, kScheme)) {
    return invalid("does not start with opc.tcp://");
  }
  std::string_view rest = url.substr(kScheme.size());
  rest = rest.substr(0, rest.find('/'));
  std::string_view host;
  std::string_view port_text;
  if (!rest.empty() && rest.front() == '[') {
    const auto close = rest.find(']');
    if (close == std::string_view::npos) {
      return invalid("unterminated IPv6 address");
    }
    host = rest.substr(1, close - 1);
    const std::string_view after = rest.substr(close + 1);
    if (!after.empty()) {
      if (after.front() != ':') {
        return invalid("junk after the IPv6 address");
      }
      port_text = after.substr(1);
    }
  } else {
    const auto colon = rest.rfind(':');
    host = rest.substr(0, colon);
    if (colon != std::string_view::npos) {
      port_text = rest.substr(colon + 1);
    }
  }
  if (host.empty()) {
    return invalid("no host");
  }
  std::uint32_t port = kDefaultPort;
  if (!port_text.empty()) {
    port = 0;
    for (const char c : port_text) {
      if (c < '0' || c > '9' || port > 65535) {
        return invalid("bad port");
      }
      port = port * 10 + static_cast<std::uint32_t>(c - '0');
    }
    if (port == 0 || port > 65535) {
      return invalid("port out of range");
    }
  }
  return std::pair<std::string, std::uint16_t>{std::string(host), static_cast<std::uint16_t>(port)};
}

void ClientChannel::open(net::EventLoop& loop, ClientTransportConfig config, OpenDone done,
                         const Clock& clock) {
  auto target = parse_endpoint_url(config.endpoint_url);
  if (!target.ok()) {
    loop.add_timer(std::chrono::nanoseconds{0},
                   [done = std::move(done), error = target.error()] { done(error); });
    return;
  }
  auto channel = std::make_shared<ClientChannel>(Token{}, loop, std::move(config), clock);
  channel->start(target->first, target->second, std::move(done));
}

ClientChannel::ClientChannel(Token, net::EventLoop& loop, ClientTransportConfig config, const Clock& clock)
    : loop_(loop), config_(std::move(config)), clock_(clock), channel_(channel_config(config_), clock) {}

ClientChannel::~ClientChannel() {
  cancel_timer(open_timer_);
  cancel_timer(tick_timer_);
  if (connection_) {
    connection_->abort();
  }
  // Every pending callback is called exactly once, even when the channel is dropped.
  fail_all(status_error(status::BadSecureChannelClosed, "the client channel was destroyed"));
}

void ClientChannel::cancel_timer(net::EventLoop::TimerId& id) {
  if (id != 0) {
    loop_.cancel_timer(id);
    id = 0;
  }
}

void ClientChannel::start(const std::string& host, std::uint16_t port, OpenDone done) {
  open_done_ = std::move(done);
  auto self = shared_from_this();
  // connect_timeout bounds the whole opening: TCP connect, HEL/ACK and OPN.
  open_timer_ = loop_.add_timer(config_.connect_timeout, [self] {
    self->open_timer_ = 0;
    self->finish_open(status_error(status::BadTimeout, fmt::format("opening a secure channel to {} timed out",
                                                                   self->config_.endpoint_url)));
  });
  net::connect_tcp(loop_, host, port, config_.connect_timeout,
                   [self](Result<std::shared_ptr<net::TcpConnection>> connection) {
                     self->on_connected(std::move(connection));
                   });
}

void ClientChannel::on_connected(Result<std::shared_ptr<net::TcpConnection>> connection) {
  if (!open_done_) {
    if (connection.ok()) {
      connection.value()->abort();  // the open already timed out
    }
    return;
  }
  if (!connection.ok()) {
    const StatusCode code =
        connection.error().code == Errc::timeout ? status::BadTimeout : status::BadConnectionRejected;
    finish_open(status_error(code, connection.error().message));
    return;
  }
  connection_ = std::move(*connection);
  std::weak_ptr<ClientChannel> weak = weak_from_this();
  connection_->set_on_data([weak](ByteSpan bytes) {
    if (auto self = weak.lock()) {
      self->channel_.receive(bytes);
      self->pump();
    }
  });
  connection_->set_on_close([weak](const Status& status) {
    if (auto self = weak.lock()) {
      self->on_connection_closed(status);
    }
  });
  channel_.start();
  pump();
}

void ClientChannel::pump() {
  if (pumping_) {
    return;  // the outer call loops until both queues are empty
  }
  auto self = shared_from_this();
  pumping_ = true;
  while (channel_.has_output() || channel_.has_events()) {
    if (channel_.has_output() && connection_) {
      connection_->send(channel_.take_output());
    }
    for (auto& event : channel_.take_events()) {
      handle(event);
    }
    if (!connection_) {
      (void)channel_.take_output();
    }
  }
  pumping_ = false;
  arm_timer();
}

void ClientChannel::handle(ChannelEvent& event) {
  switch (event.kind) {
    case ChannelEvent::Kind::Opened: {
      const auto& n = channel_.negotiated_limits();
      negotiated_.receive_buffer_size = n.receive_chunk_size;
      negotiated_.send_buffer_size = n.send_chunk_size;
      negotiated_.max_message_size = n.send_max_message;
      negotiated_.max_chunk_count = n.send_max_chunks;
      logger()->info("secure channel {} to {} open (token {}, {} ms)", channel_.channel_id(),
                     config_.endpoint_url, channel_.token().token_id, channel_.token().revised_lifetime);
      finish_open(shared_from_this());
      break;
    }
    case ChannelEvent::Kind::Renewed:
      logger()->debug("secure channel {}: token {} renewed", channel_.channel_id(),
                      channel_.token().token_id);
      break;
    case ChannelEvent::Kind::ServiceMessage:
      complete(event.request_id, std::move(*event.message));
      break;
    case ChannelEvent::Kind::Undecodable:
    case ChannelEvent::Kind::Aborted:
      complete(event.request_id,
               status_error(event.status.is_bad() ? event.status : status::BadDecodingError, event.reason));
      break;
    case ChannelEvent::Kind::Closed: {
      const StatusCode code = event.status.is_good() ? status::BadSecureChannelClosed : event.status;
      shut_down(status_error(
          code, fmt::format("secure channel to {} closed: {}", config_.endpoint_url, event.reason)));
      break;
    }
  }
}

void ClientChannel::on_connection_closed(const Status& status) {
  connection_.reset();
  if (closed_) {
    return;
  }
  const std::string why = status.ok() ? std::string("closed by the server") : status.error().message;
  shut_down(status_error(status::BadConnectionClosed,
                         fmt::format("connection to {} lost: {}", config_.endpoint_url, why)));
}

void ClientChannel::shut_down(const Error& error) {
  if (closed_ && !open_done_ && pending_.empty() && !connection_) {
    return;
  }
  const bool unexpected = !closed_;
  closed_ = true;
  cancel_timer(tick_timer_);
  if (connection_) {
    if (channel_.has_output()) {
      connection_->send(channel_.take_output());
    }
    connection_->close();
    connection_.reset();
  }
  if (open_done_) {
    finish_open(error);
    return;
  }
  fail_all(error);
  if (unexpected && on_closed_) {
    logger()->warn("{}", error.message);
    auto cb = std::move(on_closed_);
    on_closed_ = nullptr;
    cb(Status(error));
  }
}

void ClientChannel::finish_open(Result<std::shared_ptr<ClientChannel>> result) {
  cancel_timer(open_timer_);
  if (!open_done_) {
    return;
  }
  auto done = std::move(open_done_);
  open_done_ = nullptr;
  if (!result.ok()) {
    closed_ = true;
    cancel_timer(tick_timer_);
    if (connection_) {
      connection_->abort();
      connection_.reset();
    }
    logger()->warn("{}", result.error().message);
  }
  done(std::move(result));
}

void ClientChannel::send_request(const Message& request, std::chrono::milliseconds timeout,
                                 ResponseCallback cb) {
  if (!is_open()) {
    auto error = status_error(status::BadSecureChannelClosed, "the secure channel is not open");
    loop_.add_timer(std::chrono::nanoseconds{0}, [cb = std::move(cb), error] { cb(error); });
    return;
  }
  auto request_id = channel_.send_request(request);
  if (!request_id.ok()) {
    loop_.add_timer(std::chrono::nanoseconds{0},
                    [cb = std::move(cb), error = request_id.error()] { cb(error); });
    return;
  }
  const std::uint32_t id = *request_id;
  std::weak_ptr<ClientChannel> weak = weak_from_this();
  const auto timer = loop_.add_timer(timeout, [weak, id, timeout] {
    if (auto self = weak.lock()) {
      auto it = self->pending_.find(id);
      if (it != self->pending_.end()) {
        it->second.timer = 0;
        self->complete(
            id, status_error(status::BadTimeout,
                             fmt::format("no response to request {} within {} ms", id, timeout.count())));
      }
    }
  });
  pending_.emplace(id, Pending{std::move(cb), timer});
  pump();
}

void ClientChannel::complete(std::uint32_t request_id, Result<Message> result) {
  auto it = pending_.find(request_id);
  if (it == pending_.end()) {
    logger()->debug("response to request {} that is no longer pending", request_id);
    return;
  }
  auto pending = std::move(it->second);
  pending_.erase(it);
  cancel_timer(pending.timer);
  pending.callback(std::move(result));
}

void ClientChannel::fail_all(const Error& error) {
  // Callbacks may send new requests (which fail at once) or close; take the map first.
  auto pending = std::move(pending_);
  pending_.clear();
  for (auto& [id, p] : pending) {
    cancel_timer(p.timer);
    p.callback(error);
  }
}

void ClientChannel::set_on_closed(std::function<void(const Status&)> cb) {
  on_closed_ = std::move(cb);
}

void ClientChannel::close() {
  if (closed_) {
    return;
  }
  closed_ = true;
  channel_.close();  // queues CLO and reports Closed
  pump();
  shut_down(status_error(status::BadSecureChannelClosed, "the secure channel was closed"));
}

bool ClientChannel::is_open() const {
  return !closed_ && channel_.is_open();
}

const ChannelSecurityToken& ClientChannel::token() const {
  return channel_.token();
}

const TransportLimits& ClientChannel::negotiated_limits() const {
  return negotiated_;
}

void ClientChannel::arm_timer() {
  detail::arm_channel_timer(loop_, clock_, tick_timer_, closed_ ? std::nullopt : channel_.next_deadline(),
                            [weak = weak_from_this()] {
                              if (auto self = weak.lock()) {
                                self->on_channel_timer();
                              }
                            });
}

void ClientChannel::on_channel_timer() {
  tick_timer_ = 0;
  channel_.on_timer();
  pump();
}

}  // namespace sf::opcua
