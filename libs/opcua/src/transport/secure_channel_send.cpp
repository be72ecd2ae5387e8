// SecureChannel, the OpenSecureChannel handshake, sending and timers (OPC 10000-6 §6.7,
// OPC 10000-4 §5.5.2).
#include <algorithm>

#include <fmt/format.h>

#include "chunking.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/opcua/transport/secure_channel.hpp"
#include "transport/transport_log.hpp"

namespace sf::opcua {
namespace {

using detail::logger;

std::chrono::milliseconds lifetime_of(const ChannelSecurityToken& token) {
  return std::chrono::milliseconds{token.revised_lifetime};
}

}  // namespace

DateTime SecureChannel::utc_now() const {
  return DateTime::from_system_clock(clock_.utc_now());
}

std::uint32_t SecureChannel::next_sequence_number() {
  const std::uint32_t n = send_sequence_;
  // §6.7.2.4: wrap only past UInt32.MaxValue - 1024, to a value below 1024.
  send_sequence_ = n > detail::kSequenceWrapThreshold ? 1 : n + 1;
  return n;
}

std::uint32_t SecureChannel::next_request_id() {
  last_request_id_ = last_request_id_ == UINT32_MAX ? 1 : last_request_id_ + 1;
  return last_request_id_;
}

void SecureChannel::start() {
  if (config_.role != ChannelRole::Client || state_ != ChannelState::Idle) {
    return;
  }
  auto policy = policies_->get(policy_uri_);
  if (!policy.ok()) {
    set_closed(status::BadSecurityPolicyRejected, detail::reason_of(policy.error()));
    return;
  }
  policy_ = *policy;
  if (policy_->uses_certificates()) {
    auto crypto = policy_->asymmetric(config_.credentials, peer_certificate_);
    if (!crypto.ok()) {
      set_closed(status_of(crypto.error()), detail::reason_of(crypto.error()));
      return;
    }
    asymmetric_ = std::move(*crypto);
  } else {
    asymmetric_ = ChannelCrypto{SecurityPolicyNone::plain(), SecurityPolicyNone::plain()};
  }
  hello_ = make_hello(config_.limits, config_.endpoint_url);
  const Bytes bytes = encode_hello(hello_);
  output_.insert(output_.end(), bytes.begin(), bytes.end());
  state_ = ChannelState::AwaitingAck;
}

Status SecureChannel::send_open(std::uint32_t request_id, const Message& message) {
  ByteWriter body;
  SF_TRY(encode_message(message, body));
  AsymmetricSecurityHeader security;
  security.security_policy_uri = policy_uri_;
  if (policy_->uses_certificates()) {
    security.sender_certificate = config_.credentials.certificate;
    auto thumbprint = policy_->thumbprint(peer_certificate_);
    if (!thumbprint.ok()) {
      return thumbprint.error();
    }
    security.receiver_certificate_thumbprint = *thumbprint;
  }
  ByteWriter header;
  Encoder e(header);
  encode_binary(e, security);
  const std::size_t header_size = detail::kSecureHeaderSize + header.size();
  // OPN messages are a single chunk (§6.7.2.2: IsFinal is always 'F' for OPN).
  if (body.size() > detail::max_body_size(negotiated_.send_chunk_size, header_size, *asymmetric_.sending)) {
    return status_error(status::BadTcpMessageTooLarge, "OpenSecureChannel message does not fit one chunk");
  }
  detail::ChunkSpec spec;
  spec.type = MessageType::OpenSecureChannel;
  spec.channel_id = channel_id_;
  spec.security_header = header.data();
  spec.sequence_number = next_sequence_number();
  spec.request_id = request_id;
  spec.body = body.data();
  return detail::append_chunk(output_, spec, *asymmetric_.sending);
}

void SecureChannel::send_open_request(SecurityTokenRequestType type) {
  auto nonce = policy_->create_nonce();
  if (!nonce.ok()) {
    fail(status_of(nonce.error()), detail::reason_of(nonce.error()));
    return;
  }
  client_nonce_ = *nonce;
  OpenSecureChannelRequest request;
  request.request_header.timestamp = utc_now();
  request.request_header.request_handle = 0;
  request.request_header.timeout_hint = 0;
  request.client_protocol_version = kUaTcpProtocolVersion;
  request.request_type = type;
  request.security_mode = mode_;
  request.client_nonce = client_nonce_;
  request.requested_lifetime = config_.requested_lifetime_ms;
  open_request_id_ = next_request_id();
  if (auto st = send_open(open_request_id_, request); !st.ok()) {
    set_closed(status_of(st.error()), detail::reason_of(st.error()));
    return;
  }
  renew_pending_ = type == SecurityTokenRequestType::Renew;
}

void SecureChannel::on_open_request(std::uint32_t request_id, const OpenSecureChannelRequest& request) {
  const bool issue = request.request_type == SecurityTokenRequestType::Issue;
  const bool first = state_ == ChannelState::AwaitingOpen;
  if (issue != first || (!issue && request.request_type != SecurityTokenRequestType::Renew)) {
    fail(status::BadRequestTypeInvalid,
         fmt::format("OPN {} on a channel in state {}", to_string(request.request_type), to_string(state_)));
    return;
  }
  if (first) {
    // §6.7.4: None goes with mode None only; a signing policy with Sign or SignAndEncrypt.
    const bool plain = !policy_->uses_certificates();
    const bool ok = plain ? request.security_mode == MessageSecurityMode::None
                          : (request.security_mode == MessageSecurityMode::Sign ||
                             request.security_mode == MessageSecurityMode::SignAndEncrypt);
    if (!ok) {
      fail(status::BadSecurityModeRejected,
           fmt::format("mode {} with policy {}", to_string(request.security_mode), policy_uri_));
      return;
    }
    if (config_.accept_security) {
      if (auto st = config_.accept_security(policy_uri_, request.security_mode); !st.ok()) {
        fail(status_of(st.error()), detail::reason_of(st.error()));
        return;
      }
    }
    mode_ = request.security_mode;
  } else if (request.security_mode != mode_) {
    fail(status::BadSecurityModeRejected, "OPN Renew changes the security mode");
    return;
  }
  if (policy_->nonce_length() != 0 && request.client_nonce.size() != policy_->nonce_length()) {
    fail(status::BadNonceInvalid, fmt::format("client nonce of {} bytes, policy needs {}",
                                              request.client_nonce.size(), policy_->nonce_length()));
    return;
  }
  auto nonce = policy_->create_nonce();
  if (!nonce.ok()) {
    fail(status_of(nonce.error()), detail::reason_of(nonce.error()));
    return;
  }
  client_nonce_ = request.client_nonce;
  server_nonce_ = *nonce;
  auto crypto = make_symmetric_crypto(*policy_, mode_, false, client_nonce_, server_nonce_);
  if (!crypto.ok()) {
    fail(status_of(crypto.error()), detail::reason_of(crypto.error()));
    return;
  }
  if (first) {
    channel_id_ = config_.channel_id == 0 ? 1 : config_.channel_id;
  }
  ChannelSecurityToken token;
  token.channel_id = channel_id_;
  token.token_id = next_token_id_++;
  token.created_at = utc_now();
  token.revised_lifetime =
      std::clamp(request.requested_lifetime, config_.min_token_lifetime_ms, config_.max_token_lifetime_ms);

  OpenSecureChannelResponse response;
  response.response_header.timestamp = token.created_at;
  response.response_header.request_handle = request.request_header.request_handle;
  response.server_protocol_version = kUaTcpProtocolVersion;
  response.security_token = token;
  response.server_nonce = server_nonce_;
  install_token(token, std::move(*crypto), !first);
  // The response goes out under the asymmetric algorithms; the new token takes effect for
  // messages after it.
  if (auto st = send_open(request_id, response); !st.ok()) {
    fail(status_of(st.error()), detail::reason_of(st.error()));
    return;
  }
  logger()->debug("channel {}: token {} {} for {} ms", channel_id_, token.token_id,
                  first ? "issued" : "renewed", token.revised_lifetime);
}

void SecureChannel::on_open_response(std::uint32_t request_id, const OpenSecureChannelResponse& response) {
  if (request_id != open_request_id_) {
    fail(status::BadUnknownResponse,
         fmt::format("OPN response to request {}, expected {}", request_id, open_request_id_));
    return;
  }
  const StatusCode result = response.response_header.service_result;
  if (result.is_bad()) {
    set_closed(result, "OpenSecureChannel rejected");
    return;
  }
  const bool first = state_ == ChannelState::AwaitingOpen;
  const ChannelSecurityToken& token = response.security_token;
  if (token.channel_id == 0 || (!first && token.channel_id != channel_id_) || token.revised_lifetime == 0) {
    fail(status::BadSecureChannelIdInvalid,
         fmt::format("OPN response with channel {} lifetime {}", token.channel_id, token.revised_lifetime));
    return;
  }
  if (policy_->nonce_length() != 0 && response.server_nonce.size() != policy_->nonce_length()) {
    fail(status::BadNonceInvalid, "server nonce of the wrong length");
    return;
  }
  server_nonce_ = response.server_nonce;
  auto crypto = make_symmetric_crypto(*policy_, mode_, true, client_nonce_, server_nonce_);
  if (!crypto.ok()) {
    fail(status_of(crypto.error()), detail::reason_of(crypto.error()));
    return;
  }
  channel_id_ = token.channel_id;
  renew_pending_ = false;
  install_token(token, std::move(*crypto), !first);
}

void SecureChannel::install_token(const ChannelSecurityToken& token, ChannelCrypto crypto, bool renewal) {
  const auto now = clock_.now();
  if (renewal) {
    // Part 4 §5.5.2 / Part 6 §6.7.4: the old token stays usable for a while so messages in
    // flight are not lost: until the peer uses the new one (server), or until the old token's
    // end, but at least 25 % of its lifetime after the renewal.
    previous_ = std::move(current_);
    previous_until_ = std::max(previous_.expires, now + lifetime_of(previous_.token) / 4);
    peer_switched_ = false;
  }
  current_.token = token;
  current_.expires = now + lifetime_of(token);
  current_.crypto = std::move(crypto);
  current_.valid = true;
  renew_at_ = now + lifetime_of(token) * 3 / 4;
  ChannelEvent event;
  event.kind = renewal ? ChannelEvent::Kind::Renewed : ChannelEvent::Kind::Opened;
  emit(std::move(event));
  state_ = ChannelState::Open;
}

const SecureChannel::TokenState& SecureChannel::sending_token() const {
  // A server keeps securing with the old token until the client has used the new one.
  if (config_.role == ChannelRole::Server && previous_.valid && !peer_switched_) {
    return previous_;
  }
  return current_;
}

std::size_t SecureChannel::symmetric_chunk_count(std::size_t body_size) const {
  const std::size_t per_chunk = detail::max_body_size(
      negotiated_.send_chunk_size, detail::kSecureHeaderSize + 4, *sending_token().crypto.sending);
  if (per_chunk == 0) {
    return SIZE_MAX;
  }
  return std::max<std::size_t>(1, (body_size + per_chunk - 1) / per_chunk);
}

Status SecureChannel::send_symmetric(MessageType type, std::uint32_t request_id, ByteSpan body) {
  const TokenState& token = sending_token();
  const MessageCrypto& crypto = *token.crypto.sending;
  Bytes security(4);
  store_le<std::uint32_t>(security.data(), token.token.token_id);
  const std::size_t per_chunk =
      detail::max_body_size(negotiated_.send_chunk_size, detail::kSecureHeaderSize + security.size(), crypto);
  if (per_chunk == 0) {
    return status_error(status::BadTcpMessageTooLarge, "send buffer too small for one body byte");
  }
  std::size_t offset = 0;
  do {
    const std::size_t n = std::min(per_chunk, body.size() - offset);
    detail::ChunkSpec spec;
    spec.type = type;
    spec.chunk = offset + n == body.size() ? ChunkType::Final : ChunkType::Intermediate;
    spec.channel_id = channel_id_;
    spec.security_header = security;
    spec.sequence_number = next_sequence_number();
    spec.request_id = request_id;
    spec.body = body.subspan(offset, n);
    SF_TRY(detail::append_chunk(output_, spec, crypto));
    offset += n;
  } while (offset < body.size());
  return {};
}

Result<std::uint32_t> SecureChannel::send_request(const Message& request) {
  if (config_.role != ChannelRole::Client || state_ != ChannelState::Open) {
    return status_error(status::BadSecureChannelClosed, "the secure channel is not open");
  }
  ByteWriter body;
  SF_TRY(encode_message(request, body));
  const std::uint32_t max_size = negotiated_.send_max_message;
  const std::uint32_t max_chunks = negotiated_.send_max_chunks;
  const std::size_t chunks = symmetric_chunk_count(body.size());
  // Part 6 §7.1.2.4: requests beyond the server's limits are refused before anything is sent.
  if ((max_size != 0 && body.size() > max_size) || (max_chunks != 0 && chunks > max_chunks)) {
    return status_error(
        status::BadRequestTooLarge,
        fmt::format("{} of {} bytes in {} chunks exceeds the server's limits ({} bytes, {} chunks)",
                    message_type_name(request), body.size(), chunks, max_size, max_chunks));
  }
  const std::uint32_t request_id = next_request_id();
  if (auto st = send_symmetric(MessageType::SecureMessage, request_id, body.data()); !st.ok()) {
    return st.error();
  }
  return request_id;
}

void SecureChannel::send_fault(std::uint32_t request_id, std::uint32_t request_handle, StatusCode status) {
  ServiceFault fault;
  fault.response_header.timestamp = utc_now();
  fault.response_header.request_handle = request_handle;
  fault.response_header.service_result = status;
  auto body = encode_message(fault);
  if (body.ok()) {
    (void)send_symmetric(MessageType::SecureMessage, request_id, *body);
  }
}

Status SecureChannel::send_response(std::uint32_t request_id, const Message& response) {
  if (config_.role != ChannelRole::Server || state_ != ChannelState::Open) {
    return status_error(status::BadSecureChannelClosed, "the secure channel is not open");
  }
  const std::uint32_t handle = detail::request_handle_of(response);
  ByteWriter body;
  if (auto st = encode_message(response, body); !st.ok()) {
    logger()->error("channel {}: cannot encode {}: {}", channel_id_, message_type_name(response),
                    st.error().message);
    send_fault(request_id, handle, status::BadEncodingError);
    return st;
  }
  const std::uint32_t max_size = negotiated_.send_max_message;
  const std::uint32_t max_chunks = negotiated_.send_max_chunks;
  const std::size_t chunks = symmetric_chunk_count(body.size());
  if ((max_size != 0 && body.size() > max_size) || (max_chunks != 0 && chunks > max_chunks)) {
    // Part 6 §7.1.2.3: nothing has been sent yet, so the client gets a ServiceFault instead.
    logger()->warn(
        "channel {}: {} of {} bytes in {} chunks exceeds the client's limits ({} bytes, {} chunks)",
        channel_id_, message_type_name(response), body.size(), chunks, max_size, max_chunks);
    send_fault(request_id, handle, status::BadResponseTooLarge);
    return {};
  }
  return send_symmetric(MessageType::SecureMessage, request_id, body.data());
}

void SecureChannel::close() {
  if (state_ == ChannelState::Closed) {
    return;
  }
  if (config_.role == ChannelRole::Client && state_ == ChannelState::Open) {
    CloseSecureChannelRequest request;
    request.request_header.timestamp = utc_now();
    auto body = encode_message(request);
    if (body.ok()) {
      (void)send_symmetric(MessageType::CloseSecureChannel, next_request_id(), *body);
    }
  }
  set_closed(status::Good, "closed");
}

void SecureChannel::fail(StatusCode status, std::string reason) {
  if (state_ == ChannelState::Closed) {
    return;
  }
  logger()->warn("channel {} ({}): {} {}", channel_id_,
                 config_.role == ChannelRole::Server ? "server" : "client", to_string(status), reason);
  // Part 6 §7.1.3: the server reports transport errors with ERR before closing the socket.
  if (config_.role == ChannelRole::Server) {
    const Bytes bytes = encode_error(ErrorMessage{status, reason});
    output_.insert(output_.end(), bytes.begin(), bytes.end());
  }
  set_closed(status, std::move(reason));
}

void SecureChannel::set_closed(StatusCode status, std::string reason) {
  if (state_ == ChannelState::Closed) {
    return;
  }
  state_ = ChannelState::Closed;
  partial_.reset();
  input_.clear();
  input_offset_ = 0;
  current_.valid = false;
  previous_.valid = false;
  ChannelEvent event;
  event.kind = ChannelEvent::Kind::Closed;
  event.status = status;
  event.reason = std::move(reason);
  emit(std::move(event));
}

std::optional<Clock::time_point> SecureChannel::next_deadline() const {
  if (state_ != ChannelState::Open) {
    return std::nullopt;
  }
  Clock::time_point deadline = current_.expires;
  if (config_.role == ChannelRole::Client) {
    // The client gives up only once even the server's grace for the old token has passed.
    deadline = current_.expires + lifetime_of(current_.token) / 4;
    if (!renew_pending_) {
      deadline = std::min(deadline, renew_at_);
    }
  }
  if (previous_.valid) {
    deadline = std::min(deadline, previous_until_);
  }
  return deadline;
}

void SecureChannel::on_timer() {
  if (state_ != ChannelState::Open) {
    return;
  }
  const auto now = clock_.now();
  if (previous_.valid && now >= previous_until_) {
    previous_.valid = false;
  }
  if (config_.role == ChannelRole::Server) {
    if (now >= current_.expires) {
      fail(status::BadSecureChannelTokenUnknown,
           fmt::format("token {} expired without renewal", current_.token.token_id));
    }
    return;
  }
  if (now >= current_.expires + lifetime_of(current_.token) / 4) {
    set_closed(status::BadSecureChannelClosed,
               fmt::format("token {} expired without renewal", current_.token.token_id));
    return;
  }
  if (!renew_pending_ && now >= renew_at_) {
    // Part 4 §5.5.2: renew at 75 % of the lifetime.
    send_open_request(SecurityTokenRequestType::Renew);
  }
}

Bytes SecureChannel::take_output() {
  Bytes out;
  out.swap(output_);
  return out;
}

std::vector<ChannelEvent> SecureChannel::take_events() {
  std::vector<ChannelEvent> out;
  out.swap(events_);
  return out;
}

}  // namespace sf::opcua
