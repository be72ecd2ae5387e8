// The client side of UA-TCP over sf::net: connect, HEL/ACK, OPN, requests with timeouts and
// automatic token renewal at 75 % of the revised lifetime (OPC 10000-4 §5.5.2). Loop thread only.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/net/event_loop.hpp"
#include "sf/net/tcp.hpp"
#include "sf/opcua/messages.hpp"
#include "sf/opcua/transport/secure_channel.hpp"
#include "sf/opcua/transport/security_policy.hpp"
#include "sf/opcua/transport/tcp_messages.hpp"

namespace sf::opcua {

struct ClientTransportConfig {
  std::string endpoint_url;  // opc.tcp://host:port[/path]
  TransportLimits limits;
  std::uint32_t requested_lifetime_ms = 600'000;
  std::string security_policy_uri = std::string(kSecurityPolicyNoneUri);
  MessageSecurityMode security_mode = MessageSecurityMode::None;
  std::chrono::milliseconds connect_timeout{5000};
  // Limits for decoding response bodies.
  DecodeLimits decode_limits;
  // Available policies; nullptr → SecurityPolicyRegistry::standard() (None only).
  std::shared_ptr<const SecurityPolicyRegistry> policies;
  SecurityCredentials credentials;  // own certificate and key (policies other than None)
  ByteString server_certificate;    // from GetEndpoints (policies other than None)
  std::function<Status(const ByteString& certificate)> validate_certificate;
};

// "opc.tcp://host:port[/path]" → host and port (default 4840). IPv6 literals in brackets.
// Anything else → BadTcpEndpointUrlInvalid.
Result<std::pair<std::string, std::uint16_t>> parse_endpoint_url(std::string_view url);

class ClientChannel : public std::enable_shared_from_this<ClientChannel> {
 private:
  struct Token {};

 public:
  using ResponseCallback = std::function<void(Result<Message>)>;

  // TCP connect, HEL/ACK, OPN Issue; done is called once on the loop thread (errors carry the
  // StatusCode: BadConnectionRejected / BadTimeout / the server's ERR code and reason).
  static void open(net::EventLoop& loop, ClientTransportConfig config,
                   std::function<void(Result<std::shared_ptr<ClientChannel>>)> done,
                   const Clock& clock = SteadyClock::instance());

  ClientChannel(Token, net::EventLoop& loop, ClientTransportConfig config, const Clock& clock);
  ~ClientChannel();
  ClientChannel(const ClientChannel&) = delete;
  ClientChannel& operator=(const ClientChannel&) = delete;

  // Assigns the request id and sends. The caller fills the RequestHeader. The callback gets the
  // decoded response (a ServiceFault arrives as a Message too), or an Error: BadTimeout after
  // `timeout`, BadSecureChannelClosed/BadConnectionClosed when the channel dies (every pending
  // callback is called exactly once), BadRequestTooLarge when the server's limits forbid it.
  // The callback is never called from inside send_request.
  void send_request(const Message& request, std::chrono::milliseconds timeout, ResponseCallback cb);
  // Unexpected loss of the channel only (not after close()).
  void set_on_closed(std::function<void(const Status&)> cb);
  // CLO + close; pending callbacks get BadSecureChannelClosed.
  void close();
  [[nodiscard]] bool is_open() const;
  [[nodiscard]] const ChannelSecurityToken& token() const;
  // After the ACK: receive/send_buffer_size are the chunk sizes in use; max_message_size and
  // max_chunk_count the server's limits for requests (0 = none).
  [[nodiscard]] const TransportLimits& negotiated_limits() const;
  [[nodiscard]] std::size_t pending_requests() const { return pending_.size(); }

 private:
  struct Pending {
    ResponseCallback callback;
    net::EventLoop::TimerId timer = 0;
  };
  using OpenDone = std::function<void(Result<std::shared_ptr<ClientChannel>>)>;

  void start(const std::string& host, std::uint16_t port, OpenDone done);
  void on_connected(Result<std::shared_ptr<net::TcpConnection>> connection);
  void on_connection_closed(const Status& status);
  void pump();
  void handle(ChannelEvent& event);
  void complete(std::uint32_t request_id, Result<Message> result);
  void fail_all(const Error& error);
  void finish_open(Result<std::shared_ptr<ClientChannel>> result);
  void shut_down(const Error& error);
  void arm_timer();
  void on_channel_timer();
  void cancel_timer(net::EventLoop::TimerId& id);

  net::EventLoop& loop_;
  ClientTransportConfig config_;
  const Clock& clock_;
  SecureChannel channel_;
  std::shared_ptr<net::TcpConnection> connection_;
  OpenDone open_done_;
  net::EventLoop::TimerId open_timer_ = 0;
  net::EventLoop::TimerId tick_timer_ = 0;
  std::map<std::uint32_t, Pending> pending_;
  std::function<void(const Status&)> on_closed_;
  TransportLimits negotiated_;
  bool closed_ = false;
  bool pumping_ = false;
};

}  // namespace sf::opcua
