// SecureChannel: the sans-I/O UA-TCP connection and secure channel protocol of one connection
// (OPC 10000-6 §6.7 and §7.1), for either role. It owns no socket and no timer:
//   - receive(bytes) takes whatever arrived; complete chunks are processed at once;
//   - take_output() returns the bytes to write to the connection, in order;
//   - take_events() returns what the owner must act on (opened, messages, closed, ...);
//   - on_timer() at next_deadline() drives token renewal (client) and expiry (server).
// Time comes from the injected Clock, so token lifetimes are testable with ManualClock.
//
// Transport violations (bad header, wrong channel id, bad sequence number, unknown token, limit
// exceeded) make the channel send ERR (server) and close; a Closed event is always the last.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/codec.hpp"
#include "sf/opcua/messages.hpp"
#include "sf/opcua/transport/security_policy.hpp"
#include "sf/opcua/transport/tcp_messages.hpp"

namespace sf::opcua {

enum class ChannelRole : std::uint8_t { Client, Server };

struct SecureChannelConfig {
  ChannelRole role = ChannelRole::Server;
  TransportLimits limits;
  // Limits for decoding message bodies (strings, arrays, nesting).
  DecodeLimits decode_limits;
  // Policies accepted (server) / available (client); nullptr → SecurityPolicyRegistry::standard().
  std::shared_ptr<const SecurityPolicyRegistry> policies;
  // Own certificate and key (policies other than None).
  SecurityCredentials credentials;
  // Checks the peer's certificate (policies other than None); nullptr accepts any.
  std::function<Status(const ByteString& certificate)> validate_certificate;
  // Server: whether the endpoint offers this policy and mode (nullptr: every registered policy
  // with the modes it allows). A refusal closes the channel with the status returned.
  std::function<Status(std::string_view policy_uri, MessageSecurityMode mode)> accept_security;

  // Server: the channel id, unique per server and non-zero (assigned by the owner).
  std::uint32_t channel_id = 0;
  // Server: requested token lifetimes are clamped to [min, max].
  std::uint32_t max_token_lifetime_ms = 3'600'000;
  std::uint32_t min_token_lifetime_ms = 10'000;

  // Client: what to ask for.
  std::string endpoint_url;
  std::string security_policy_uri = std::string(kSecurityPolicyNoneUri);
  MessageSecurityMode security_mode = MessageSecurityMode::None;
  std::uint32_t requested_lifetime_ms = 600'000;
  ByteString server_certificate;  // DER, from GetEndpoints (policies other than None)

  // The first sequence number this side sends (tests start near the wrap-around).
  std::uint32_t first_sequence_number = 1;
};

enum class ChannelState : std::uint8_t {
  Idle,          // client before start(); server waiting for HEL
  AwaitingAck,   // client: HEL sent
  AwaitingOpen,  // server: ACK sent, waiting for OPN; client: OPN Issue sent
  Open,          // a token is valid
  Closed,        // final
};
std::string_view to_string(ChannelState state);

struct ChannelEvent {
  enum class Kind : std::uint8_t {
    // The first token was issued (server) / received (client).
    Opened,
    // A new token was issued (server) / received (client).
    Renewed,
    // A decoded service message: a request (server) or a response (client). OPN/CLO never
    // arrive as ServiceMessage events.
    ServiceMessage,
    // Server: a request that could not be decoded; answer a ServiceFault with `status`
    // (BadServiceUnsupported for an unknown type, BadDecodingError otherwise) and
    // `request_handle` (0 when even the RequestHeader was unreadable).
    // Client: a response that could not be decoded; fail request `request_id` with `status`.
    Undecodable,
    // The peer aborted message `request_id` with an 'A' chunk; `status` and `reason` are its.
    Aborted,
    // The channel is closed (always the last event). `status` Good: an orderly close (CLO or
    // close()); otherwise the error, which was sent as ERR when this side detected it.
    Closed,
  };
  Kind kind = Kind::ServiceMessage;
  std::uint32_t request_id = 0;
  std::optional<Message> message;
  StatusCode status;
  std::uint32_t request_handle = 0;
  std::string reason;
};

class SecureChannel {
 public:
  SecureChannel(SecureChannelConfig config, const Clock& clock);
  ~SecureChannel();
  SecureChannel(const SecureChannel&) = delete;
  SecureChannel& operator=(const SecureChannel&) = delete;

  // Client: queues the HEL; the OPN Issue follows the ACK on its own.
  void start();
  // Takes received bytes (any split). Ignored once closed.
  void receive(ByteSpan bytes);

  // Client: assigns the request id, encodes and chunks the request. Errors: not open →
  // BadSecureChannelClosed; larger than the server's maxMessageSize/maxChunkCount →
  // BadRequestTooLarge; encoding failure → the encoder's status.
  Result<std::uint32_t> send_request(const Message& request);
  // Server: encodes and chunks the response for request_id. If it exceeds the client's
  // maxMessageSize/maxChunkCount, a ServiceFault BadResponseTooLarge with the same
  // requestHandle goes out instead (§6.7.2.1). Errors: not open, encoding failure (then a
  // ServiceFault BadEncodingError is sent).
  Status send_response(std::uint32_t request_id, const Message& response);

  // Orderly close: the client sends CLO; both sides then report Closed (Good).
  void close();
  // Sends ERR(status, reason) when this side may (server, or client after HEL) and closes.
  void fail(StatusCode status, std::string reason);

  // The earliest time on_timer() has work (token renewal, expiry, old-token overlap end).
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const;
  void on_timer();

  // Bytes to send, in order (empties the queue).
  Bytes take_output();
  [[nodiscard]] bool has_output() const { return !output_.empty(); }
  // Events since the last call, in order.
  std::vector<ChannelEvent> take_events();
  [[nodiscard]] bool has_events() const { return !events_.empty(); }

  [[nodiscard]] ChannelRole role() const { return config_.role; }
  [[nodiscard]] ChannelState state() const { return state_; }
  [[nodiscard]] bool is_open() const { return state_ == ChannelState::Open; }
  [[nodiscard]] bool is_closed() const { return state_ == ChannelState::Closed; }
  [[nodiscard]] std::uint32_t channel_id() const { return channel_id_; }
  // The newest token (zero before Opened).
  [[nodiscard]] const ChannelSecurityToken& token() const { return current_.token; }
  [[nodiscard]] const NegotiatedLimits& negotiated_limits() const { return negotiated_; }
  // From the HEL (server) / the config (client).
  [[nodiscard]] const std::string& endpoint_url() const { return endpoint_url_; }
  [[nodiscard]] const std::string& security_policy_uri() const { return policy_uri_; }
  [[nodiscard]] MessageSecurityMode security_mode() const { return mode_; }
  [[nodiscard]] const ByteString& peer_certificate() const { return peer_certificate_; }

 private:
  struct TokenState {
    ChannelSecurityToken token;
    Clock::time_point expires{};
    ChannelCrypto crypto;
    bool valid = false;
  };
  struct Partial {  // a message being assembled from 'C' chunks (§6.7.2.2)
    std::uint32_t request_id = 0;
    std::uint32_t chunks = 0;
    Bytes body;
  };

  // Receiving (secure_channel.cpp).
  void process_buffer();
  void process_chunk(const MessageHeader& header, ByteSpan chunk);
  void on_hello(ByteSpan chunk);
  void on_acknowledge(ByteSpan chunk);
  void on_error(ByteSpan chunk);
  void on_open_chunk(ByteSpan chunk);
  void on_symmetric_chunk(const MessageHeader& header, ByteSpan chunk);
  void on_message_chunk(const MessageHeader& header, std::uint32_t request_id, ByteSpan body);
  void on_open_request(std::uint32_t request_id, const OpenSecureChannelRequest& request);
  void on_open_response(std::uint32_t request_id, const OpenSecureChannelResponse& response);
  void deliver(std::uint32_t request_id, ByteSpan body);
  bool check_open_header(std::uint32_t channel_id, const AsymmetricSecurityHeader& header);
  bool accept_sequence_number(std::uint32_t sequence_number);
  TokenState* find_token(std::uint32_t token_id);
  [[nodiscard]] std::uint32_t receive_chunk_limit() const;

  // Sending (secure_channel_send.cpp).
  void send_open_request(SecurityTokenRequestType type);
  Status send_open(std::uint32_t request_id, const Message& message);
  Status send_symmetric(MessageType type, std::uint32_t request_id, ByteSpan body);
  [[nodiscard]] const TokenState& sending_token() const;
  [[nodiscard]] std::size_t symmetric_chunk_count(std::size_t body_size) const;
  void send_fault(std::uint32_t request_id, std::uint32_t request_handle, StatusCode status);
  std::uint32_t next_sequence_number();
  std::uint32_t next_request_id();
  [[nodiscard]] DateTime utc_now() const;

  void set_closed(StatusCode status, std::string reason);
  void emit(ChannelEvent event) { events_.push_back(std::move(event)); }
  void install_token(const ChannelSecurityToken& token, ChannelCrypto crypto, bool renewal);

  SecureChannelConfig config_;
  const Clock& clock_;
  std::shared_ptr<const SecurityPolicyRegistry> policies_;
  std::shared_ptr<const SecurityPolicy> policy_;
  ChannelState state_ = ChannelState::Idle;

  Bytes input_;
  std::size_t input_offset_ = 0;
  Bytes output_;
  std::vector<ChannelEvent> events_;
  Bytes scratch_;

  std::uint32_t channel_id_ = 0;
  std::string endpoint_url_;
  std::string policy_uri_;
  MessageSecurityMode mode_ = MessageSecurityMode::None;
  ByteString peer_certificate_;
  HelloMessage hello_;
  NegotiatedLimits negotiated_;
  bool negotiated_set_ = false;
  ChannelCrypto asymmetric_;

  TokenState current_;   // newest token
  TokenState previous_;  // the one before, valid during the renewal overlap
  Clock::time_point previous_until_{};
  bool peer_switched_ = false;  // server: the client used the newest token
  std::uint32_t next_token_id_ = 1;
  ByteString client_nonce_;
  ByteString server_nonce_;
  bool renew_pending_ = false;         // client: OPN Renew sent
  std::uint32_t open_request_id_ = 0;  // client: request id of the pending OPN
  Clock::time_point renew_at_{};       // client: 75 % of the lifetime

  std::uint32_t send_sequence_ = 0;
  std::optional<std::uint32_t> receive_sequence_;
  std::uint32_t last_request_id_ = 0;
  std::optional<Partial> partial_;
};

}  // namespace sf::opcua
