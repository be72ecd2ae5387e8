// SecureChannel, receiving side: stream → chunks → messages (OPC 10000-6 §6.7, §7.1).
#include "sf/opcua/transport/secure_channel.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "chunking.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"
#include "transport/transport_log.hpp"

namespace sf::opcua {
namespace {

using detail::logger;

// Consumed input is dropped once it is this large and more than half the buffer.
constexpr std::size_t kCompactThreshold = 64U * 1024U;

}  // namespace

std::string_view to_string(ChannelState state) {
  switch (state) {
    case ChannelState::Idle:
      return "Idle";
    case ChannelState::AwaitingAck:
      return "AwaitingAck";
    case ChannelState::AwaitingOpen:
      return "AwaitingOpen";
    case ChannelState::Open:
      return "Open";
    case ChannelState::Closed:
      return "Closed";
  }
  return "?";
}

SecureChannel::SecureChannel(SecureChannelConfig config, const Clock& clock)
    : config_(std::move(config)), clock_(clock), policies_(config_.policies) {
  if (!policies_) {
    policies_ = SecurityPolicyRegistry::standard();
  }
  send_sequence_ = config_.first_sequence_number;
  if (config_.role == ChannelRole::Client) {
    endpoint_url_ = config_.endpoint_url;
    policy_uri_ = config_.security_policy_uri;
    mode_ = config_.security_mode;
    peer_certificate_ = config_.server_certificate;
  }
}

SecureChannel::~SecureChannel() = default;

void SecureChannel::receive(ByteSpan bytes) {
  if (state_ == ChannelState::Closed || bytes.empty()) {
    return;
  }
  input_.insert(input_.end(), bytes.begin(), bytes.end());
  process_buffer();
}

std::uint32_t SecureChannel::receive_chunk_limit() const {
  if (negotiated_set_) {
    return negotiated_.receive_chunk_size;
  }
  // Before HEL/ACK only HEL, ACK or ERR may arrive; they are small.
  return std::max(config_.limits.receive_buffer_size, kMinBufferSize);
}

void SecureChannel::process_buffer() {
  while (state_ != ChannelState::Closed) {
    const ByteSpan pending = ByteSpan(input_).subspan(input_offset_);
    if (pending.size() < kMessageHeaderSize) {
      break;
    }
    auto header = decode_header(pending);
    if (!header.ok()) {
      fail(status_of(header.error()), detail::reason_of(header.error()));
      return;
    }
    // §7.1.2: the connection layer checks MessageSize against the negotiated ReceiveBufferSize
    // before passing a chunk on.
    if (header->size > receive_chunk_limit()) {
      fail(status::BadTcpMessageTooLarge,
           fmt::format("{} chunk of {} bytes exceeds the receive buffer of {}", to_string(header->type),
                       header->size, receive_chunk_limit()));
      return;
    }
    if (pending.size() < header->size) {
      break;
    }
    input_offset_ += header->size;
    process_chunk(*header, pending.first(header->size));
  }
  if (input_offset_ == input_.size()) {
    input_.clear();
    input_offset_ = 0;
  } else if (input_offset_ > kCompactThreshold && input_offset_ * 2 > input_.size()) {
    input_.erase(input_.begin(), input_.begin() + static_cast<std::ptrdiff_t>(input_offset_));
    input_offset_ = 0;
  }
}

void SecureChannel::process_chunk(const MessageHeader& header, ByteSpan chunk) {
  const bool server = config_.role == ChannelRole::Server;
  const MessageType type = header.type;
  if (type == MessageType::Error && !server && state_ != ChannelState::Idle) {
    on_error(chunk);
    return;
  }
  switch (state_) {
    case ChannelState::Idle:
      if (server && type == MessageType::Hello) {
        on_hello(chunk);
        return;
      }
      break;
    case ChannelState::AwaitingAck:
      if (type == MessageType::Acknowledge) {
        on_acknowledge(chunk);
        return;
      }
      break;
    case ChannelState::AwaitingOpen:
      if (type == MessageType::OpenSecureChannel) {
        on_open_chunk(chunk);
        return;
      }
      if (server && (type == MessageType::SecureMessage || type == MessageType::CloseSecureChannel)) {
        fail(status::BadTcpSecureChannelUnknown,
             fmt::format("{} before the secure channel was opened", to_string(type)));
        return;
      }
      break;
    case ChannelState::Open:
      if (type == MessageType::OpenSecureChannel) {
        on_open_chunk(chunk);
        return;
      }
      if (type == MessageType::SecureMessage || (server && type == MessageType::CloseSecureChannel)) {
        on_symmetric_chunk(header, chunk);
        return;
      }
      break;
    case ChannelState::Closed:
      return;
  }
  fail(status::BadTcpMessageTypeInvalid,
       fmt::format("unexpected {} message in state {}", to_string(type), to_string(state_)));
}

void SecureChannel::on_hello(ByteSpan chunk) {
  auto hello = decode_hello_body(chunk.subspan(kMessageHeaderSize));
  if (!hello.ok()) {
    fail(status_of(hello.error()), detail::reason_of(hello.error()));
    return;
  }
  auto ack = negotiate_acknowledge(*hello, config_.limits);
  if (!ack.ok()) {
    fail(status_of(ack.error()), detail::reason_of(ack.error()));
    return;
  }
  hello_ = *hello;
  endpoint_url_ = hello->endpoint_url;
  negotiated_ = server_limits(*hello, *ack);
  negotiated_set_ = true;
  const Bytes bytes = encode_acknowledge(*ack);
  output_.insert(output_.end(), bytes.begin(), bytes.end());
  state_ = ChannelState::AwaitingOpen;
  logger()->debug("HEL for '{}': chunks {}/{} bytes, max message {}, max chunks {}", endpoint_url_,
                  negotiated_.receive_chunk_size, negotiated_.send_chunk_size, negotiated_.send_max_message,
                  negotiated_.send_max_chunks);
}

void SecureChannel::on_acknowledge(ByteSpan chunk) {
  auto ack = decode_acknowledge_body(chunk.subspan(kMessageHeaderSize));
  if (!ack.ok()) {
    fail(status_of(ack.error()), detail::reason_of(ack.error()));
    return;
  }
  auto limits = client_limits(hello_, *ack);
  if (!limits.ok()) {
    fail(status_of(limits.error()), detail::reason_of(limits.error()));
    return;
  }
  negotiated_ = *limits;
  negotiated_set_ = true;
  state_ = ChannelState::AwaitingOpen;
  send_open_request(SecurityTokenRequestType::Issue);
}

void SecureChannel::on_error(ByteSpan chunk) {
  auto error = decode_error_body(chunk.subspan(kMessageHeaderSize));
  if (!error.ok()) {
    set_closed(status::BadTcpMessageTypeInvalid, "malformed ERR message: " + error.error().message);
    return;
  }
  logger()->warn("peer sent ERR {}: {}", to_string(error->error), error->reason);
  const StatusCode code = error->error.is_bad() ? error->error : status::BadCommunicationError;
  set_closed(code, error->reason.empty() ? std::string(code.name()) : error->reason);
}

bool SecureChannel::check_open_header(std::uint32_t channel_id, const AsymmetricSecurityHeader& header) {
  const bool server = config_.role == ChannelRole::Server;
  const bool first = state_ == ChannelState::AwaitingOpen;
  // The first OPN of a client carries SecureChannelId 0 and its response the id the server
  // assigned; every later one the channel's id.
  const bool id_ok = first ? (server ? channel_id == 0 : channel_id != 0) : channel_id == channel_id_;
  if (!id_ok) {
    fail(status::BadTcpSecureChannelUnknown, fmt::format("OPN for unknown secure channel {}", channel_id));
    return false;
  }
  if (server && first) {
    auto policy = policies_->get(header.security_policy_uri.view());
    if (!policy.ok()) {
      fail(status::BadSecurityPolicyRejected, detail::reason_of(policy.error()));
      return false;
    }
    policy_ = *policy;
    policy_uri_ = header.security_policy_uri.str();
  } else if (header.security_policy_uri.view() != policy_uri_) {
    fail(status::BadSecurityPolicyRejected, fmt::format("OPN with policy '{}' on a channel using '{}'",
                                                        header.security_policy_uri.view(), policy_uri_));
    return false;
  }
  if (!policy_->uses_certificates()) {
    // None: certificates are ignored (some clients send theirs anyway).
    asymmetric_ = ChannelCrypto{SecurityPolicyNone::plain(), SecurityPolicyNone::plain()};
    return true;
  }
  if (server && first) {
    peer_certificate_ = header.sender_certificate;
  } else if (!(header.sender_certificate == peer_certificate_)) {
    fail(status::BadSecurityChecksFailed, "OPN sender certificate differs from the channel's");
    return false;
  }
  if (config_.validate_certificate) {
    if (auto st = config_.validate_certificate(peer_certificate_); !st.ok()) {
      fail(status_of(st.error()), detail::reason_of(st.error()));
      return false;
    }
  }
  auto own = policy_->thumbprint(config_.credentials.certificate);
  if (!own.ok() || !(own.value() == header.receiver_certificate_thumbprint)) {
    fail(status::BadCertificateInvalid, "OPN receiver certificate thumbprint does not match our certificate");
    return false;
  }
  auto crypto = policy_->asymmetric(config_.credentials, peer_certificate_);
  if (!crypto.ok()) {
    fail(status_of(crypto.error()), detail::reason_of(crypto.error()));
    return false;
  }
  asymmetric_ = std::move(*crypto);
  return true;
}

void SecureChannel::on_open_chunk(ByteSpan chunk) {
  ByteReader reader(chunk.subspan(kMessageHeaderSize));
  const std::uint32_t channel_id = reader.u32();
  DecodeOptions options;
  options.limits = config_.decode_limits;
  Decoder decoder(reader, options);
  AsymmetricSecurityHeader security;
  decode_binary(decoder, security);
  if (!decoder.ok()) {
    fail(status::BadDecodingError, "malformed OPN security header: " + decoder.error().message);
    return;
  }
  if (!check_open_header(channel_id, security)) {
    return;
  }
  auto plain =
      detail::open_chunk(chunk, kMessageHeaderSize + reader.position(), *asymmetric_.receiving, scratch_);
  if (!plain.ok()) {
    fail(status_of(plain.error()), "OPN: " + detail::reason_of(plain.error()));
    return;
  }
  ByteReader seq(*plain);
  const std::uint32_t sequence_number = seq.u32();
  const std::uint32_t request_id = seq.u32();
  if (!seq.ok()) {
    fail(status::BadDecodingError, "OPN without sequence header");
    return;
  }
  if (!accept_sequence_number(sequence_number)) {
    return;
  }
  auto message = decode_message(seq.rest(), options);
  if (!message.ok()) {
    fail(status::BadDecodingError, "OPN body: " + message.error().message);
    return;
  }
  if (config_.role == ChannelRole::Server) {
    if (const auto* request = std::get_if<OpenSecureChannelRequest>(&*message)) {
      on_open_request(request_id, *request);
      return;
    }
  } else {
    if (const auto* response = std::get_if<OpenSecureChannelResponse>(&*message)) {
      on_open_response(request_id, *response);
      return;
    }
    if (const auto* fault = std::get_if<ServiceFault>(&*message)) {
      set_closed(fault->response_header.service_result.is_bad() ? fault->response_header.service_result
                                                                : status::BadUnknownResponse,
                 "OpenSecureChannel rejected with a ServiceFault");
      return;
    }
  }
  fail(status::BadDecodingError, fmt::format("OPN carries a {}", message_type_name(*message)));
}

bool SecureChannel::accept_sequence_number(std::uint32_t sequence_number) {
  // §6.7.2.4: +1 per chunk; after UInt32.MaxValue - 1024 the sender may wrap to below 1024.
  if (receive_sequence_) {
    const std::uint32_t last = *receive_sequence_;
    const bool next = last != UINT32_MAX && sequence_number == last + 1;
    const bool wrapped =
        last > detail::kSequenceWrapThreshold && sequence_number < detail::kSequenceWrapLimit;
    if (!next && !wrapped) {
      fail(status::BadSequenceNumberInvalid,
           fmt::format("sequence number {} after {}", sequence_number, last));
      return false;
    }
  }
  receive_sequence_ = sequence_number;
  return true;
}

SecureChannel::TokenState* SecureChannel::find_token(std::uint32_t token_id) {
  if (current_.valid && current_.token.token_id == token_id) {
    return &current_;
  }
  if (previous_.valid && previous_.token.token_id == token_id) {
    if (clock_.now() < previous_until_) {
      return &previous_;
    }
    previous_.valid = false;
  }
  return nullptr;
}

void SecureChannel::on_symmetric_chunk(const MessageHeader& header, ByteSpan chunk) {
  ByteReader reader(chunk.subspan(kMessageHeaderSize));
  const std::uint32_t channel_id = reader.u32();
  const std::uint32_t token_id = reader.u32();
  if (!reader.ok()) {
    fail(status::BadDecodingError,
         fmt::format("{} chunk of {} bytes is too short", to_string(header.type), chunk.size()));
    return;
  }
  if (channel_id != channel_id_) {
    fail(status::BadTcpSecureChannelUnknown, fmt::format("{} for secure channel {} on channel {}",
                                                         to_string(header.type), channel_id, channel_id_));
    return;
  }
  TokenState* token = find_token(token_id);
  if (token == nullptr) {
    fail(status::BadSecureChannelTokenUnknown, fmt::format("unknown or expired token {}", token_id));
    return;
  }
  if (token == &current_ && config_.role == ChannelRole::Server && !peer_switched_) {
    // Part 4 §5.5.2: the client uses the new token, so the old one is no longer accepted and
    // the server secures its responses with the new one from now on.
    peer_switched_ = true;
    previous_.valid = false;
  }
  auto plain =
      detail::open_chunk(chunk, kMessageHeaderSize + reader.position(), *token->crypto.receiving, scratch_);
  if (!plain.ok()) {
    fail(status_of(plain.error()),
         fmt::format("{}: {}", to_string(header.type), detail::reason_of(plain.error())));
    return;
  }
  ByteReader seq(*plain);
  const std::uint32_t sequence_number = seq.u32();
  const std::uint32_t request_id = seq.u32();
  if (!seq.ok()) {
    fail(status::BadDecodingError, fmt::format("{} without sequence header", to_string(header.type)));
    return;
  }
  if (!accept_sequence_number(sequence_number)) {
    return;
  }
  if (header.type == MessageType::CloseSecureChannel) {
    // §6.7.4 / Part 4 §5.5.3: the server closes without answering.
    logger()->debug("channel {}: CloseSecureChannel from the client", channel_id_);
    set_closed(status::Good, "closed by the client");
    return;
  }
  on_message_chunk(header, request_id, seq.rest());
}

void SecureChannel::on_message_chunk(const MessageHeader& header, std::uint32_t request_id, ByteSpan body) {
  // §6.7.2: chunks of one message are sent back to back, never interleaved with others.
  if (partial_ && partial_->request_id != request_id) {
    fail(status::BadTcpMessageTypeInvalid,
         fmt::format("chunk of request {} inside message {}", request_id, partial_->request_id));
    return;
  }
  if (header.chunk == ChunkType::Abort) {
    // §6.7.3: the body is the error StatusCode and a reason; the partial message is dropped.
    partial_.reset();
    ByteReader r(body);
    Decoder d(r);
    StatusCode error;
    String reason;
    decode_binary(d, error);
    decode_binary(d, reason);
    logger()->warn("channel {}: peer aborted message {}: {} {}", channel_id_, request_id, to_string(error),
                   reason.view());
    ChannelEvent event;
    event.kind = ChannelEvent::Kind::Aborted;
    event.request_id = request_id;
    event.status = d.ok() ? error : status::BadDecodingError;
    event.reason = reason.str();
    emit(std::move(event));
    return;
  }
  if (!partial_) {
    partial_ = Partial{request_id, 0, {}};
  }
  partial_->chunks += 1;
  partial_->body.insert(partial_->body.end(), body.begin(), body.end());
  const std::uint32_t max_chunks = negotiated_.receive_max_chunks;
  const std::uint32_t max_size = negotiated_.receive_max_message;
  if (max_chunks != 0 && partial_->chunks > max_chunks) {
    fail(status::BadEncodingLimitsExceeded,
         fmt::format("message {} has more than {} chunks", request_id, max_chunks));
    return;
  }
  if (max_size != 0 && partial_->body.size() > max_size) {
    fail(status::BadTcpMessageTooLarge,
         fmt::format("message {} is larger than {} bytes", request_id, max_size));
    return;
  }
  if (header.chunk == ChunkType::Final) {
    const Bytes complete = std::move(partial_->body);
    partial_.reset();
    deliver(request_id, complete);
  }
}

void SecureChannel::deliver(std::uint32_t request_id, ByteSpan body) {
  DecodeOptions options;
  options.limits = config_.decode_limits;
  auto message = decode_message(body, options);
  const bool server = config_.role == ChannelRole::Server;
  if (message.ok() && (!server || detail::is_request(*message))) {
    ChannelEvent event;
    event.kind = ChannelEvent::Kind::ServiceMessage;
    event.request_id = request_id;
    event.message = std::move(*message);
    emit(std::move(event));
    return;
  }
  ChannelEvent event;
  event.kind = ChannelEvent::Kind::Undecodable;
  event.request_id = request_id;
  if (!server) {
    event.status = status::BadDecodingError;
    event.reason = message.error().message;
    logger()->warn("channel {}: response {} undecodable: {}", channel_id_, request_id, event.reason);
    emit(std::move(event));
    return;
  }
  // Read as much as possible for the ServiceFault: the type NodeId and the RequestHeader.
  ByteReader r(body);
  Decoder d(r, options);
  NodeId type_id;
  RequestHeader request_header;
  decode_binary(d, type_id);
  if (d.ok()) {
    decode_binary(d, request_header);
    if (d.ok()) {
      event.request_handle = request_header.request_handle;
    }
  }
  const bool unknown_type = message.ok() || status_of(message.error()) == status::BadDataTypeIdUnknown;
  event.status = unknown_type ? status::BadServiceUnsupported : status::BadDecodingError;
  event.reason = message.ok() ? fmt::format("{} is not a service request", message_type_name(*message))
                              : message.error().message;
  logger()->warn("channel {}: request {} ({}) rejected with {}: {}", channel_id_, request_id,
                 to_string(type_id), to_string(event.status), event.reason);
  emit(std::move(event));
}

}  // namespace sf::opcua
