// The server side of UA-TCP over sf::net: a listener that runs one SecureChannel per
// connection and hands decoded service requests to a ServiceHandler. Loop thread only.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/net/event_loop.hpp"
#include "sf/opcua/messages.hpp"
#include "sf/opcua/transport/security_policy.hpp"
#include "sf/opcua/transport/tcp_messages.hpp"

namespace sf::opcua {

struct ChannelInfo {
  std::uint32_t channel_id = 0;
  std::string peer;                 // "127.0.0.1:53124"
  std::string endpoint_url;         // from HEL
  std::string security_policy_uri;  // from OPN
  MessageSecurityMode security_mode = MessageSecurityMode::None;
  ByteString client_certificate;  // sender certificate of the OPN
};

// One open secure channel; loop thread only.
class ServerChannel {
 public:
  virtual ~ServerChannel() = default;
  [[nodiscard]] virtual const ChannelInfo& info() const = 0;
  // Encodes and sends the response for request_id, chunked to the negotiated limits. If it
  // exceeds the client's maxMessageSize/maxChunkCount, sends a ServiceFault BadResponseTooLarge
  // with the same requestHandle instead (Part 6 §6.7.2.1). Ignored once the channel is closed.
  virtual void send_response(std::uint32_t request_id, const Message& response) = 0;
  // Closes the channel and its connection (after flushing what is queued).
  virtual void close() = 0;
  [[nodiscard]] virtual bool is_open() const = 0;
};

class ServiceHandler {
 public:
  virtual ~ServiceHandler() = default;
  // A decoded service request (OPN/CLO are the transport's own business). Loop thread.
  // Requests whose body cannot be decoded never get here: the transport answers them with a
  // ServiceFault (BadServiceUnsupported / BadDecodingError) itself.
  virtual void on_request(const std::shared_ptr<ServerChannel>& channel, std::uint32_t request_id,
                          Message request) = 0;
  // The channel is gone (CLO, error, lost connection, stop()).
  virtual void on_channel_closed(std::uint32_t channel_id) { (void)channel_id; }
  // Whether an activated session uses the channel: the transport never evicts such a channel
  // to make room for a new connection.
  [[nodiscard]] virtual bool holds_session(std::uint32_t channel_id) const {
    (void)channel_id;
    return false;
  }
};

struct ServerTransportConfig {
  std::string host = "0.0.0.0";
  std::uint16_t port = 4840;  // 0 = any free port
  TransportLimits limits;
  // Connections (with a secure channel or on their way to one). When all are taken, a new
  // connection takes the place of the oldest one that has not opened a channel, else of the
  // oldest channel without an activated session (ServiceHandler::holds_session); when every
  // channel holds a session it gets ERR BadTcpNotEnoughResources. Idle connections therefore
  // cannot lock real clients out.
  std::size_t max_channels = 100;
  // The same rule among the connections of one source address (0: only max_channels).
  std::size_t max_channels_per_address = 50;
  std::chrono::milliseconds hello_timeout{3000};  // connection without HEL/OPN is closed
  std::uint32_t max_token_lifetime_ms = 3'600'000;
  std::uint32_t min_token_lifetime_ms = 10'000;
  // Limits for decoding request bodies.
  DecodeLimits decode_limits;
  // Accepted security policies; nullptr → SecurityPolicyRegistry::standard() (None only).
  std::shared_ptr<const SecurityPolicyRegistry> policies;
  // Own certificate and key (for policies other than None).
  SecurityCredentials credentials;
  // Checks client certificates (policies other than None); nullptr accepts any.
  std::function<Status(const ByteString& certificate)> validate_certificate;
  // Whether a policy and mode are offered (see SecureChannelConfig::accept_security).
  std::function<Status(std::string_view policy_uri, MessageSecurityMode mode)> accept_security;
};

class ServerTransport {
 public:
  // Binds and listens (loop thread). Errors carry BadResourceUnavailable with host:port and
  // the errno text.
  static Result<std::unique_ptr<ServerTransport>> start(net::EventLoop& loop, ServerTransportConfig config,
                                                        ServiceHandler& handler,
                                                        const Clock& clock = SteadyClock::instance());
  ~ServerTransport();
  ServerTransport(const ServerTransport&) = delete;
  ServerTransport& operator=(const ServerTransport&) = delete;

  [[nodiscard]] std::uint16_t port() const;
  // Connections with a secure channel or on their way to one.
  [[nodiscard]] std::size_t channel_count() const;
  // Closes the listener and all channels (on_channel_closed for each open one). Idempotent.
  void stop();

  struct Impl;

 private:
  explicit ServerTransport(std::shared_ptr<Impl> impl);
  std::shared_ptr<Impl> impl_;
};

}  // namespace sf::opcua
