// UA-TCP (OPC 10000-6 §7.1): the 8-byte message header shared by every message and chunk, the
// connection protocol messages Hello, Acknowledge and Error, and the buffer negotiation.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/status_code.hpp"

namespace sf::opcua {

// OPC 10000-6 §7.1.2.2: the three ASCII bytes of MessageType.
enum class MessageType : std::uint8_t {
  Hello,              // HEL
  Acknowledge,        // ACK
  Error,              // ERR
  ReverseHello,       // RHE
  OpenSecureChannel,  // OPN
  SecureMessage,      // MSG
  CloseSecureChannel  // CLO
};
// 'F' final chunk, 'C' intermediate chunk, 'A' abort (§6.7.2.2). HEL/ACK/ERR/RHE always use 'F'.
enum class ChunkType : std::uint8_t { Final = 'F', Intermediate = 'C', Abort = 'A' };

std::string_view to_string(MessageType type);  // "HEL", ...
std::optional<MessageType> message_type_from(ByteSpan three_bytes);

// The UA-TCP protocol version this stack speaks (§7.1.2.3).
inline constexpr std::uint32_t kUaTcpProtocolVersion = 0;
inline constexpr std::size_t kMessageHeaderSize = 8;
// §7.1.2.3: buffers are at least 8192 bytes; the endpoint URL at most 4096 bytes.
inline constexpr std::uint32_t kMinBufferSize = 8192;
inline constexpr std::size_t kMaxEndpointUrlLength = 4096;

struct MessageHeader {
  MessageType type = MessageType::SecureMessage;
  ChunkType chunk = ChunkType::Final;
  std::uint32_t size = 0;  // of the whole message/chunk, header included

  friend bool operator==(const MessageHeader&, const MessageHeader&) = default;
};

void encode_header(ByteWriter& w, const MessageHeader& header);
// Decodes the first 8 bytes of `bytes`. An unknown type, or a chunk type other than 'F' for
// OPN/CLO or other than F/C/A for MSG → BadTcpMessageTypeInvalid (the byte is ignored for
// HEL/ACK/ERR/RHE); a size below 8 or fewer than 8 bytes → BadDecodingError.
Result<MessageHeader> decode_header(ByteSpan bytes);

// §7.1.2.3
struct HelloMessage {
  std::uint32_t protocol_version = kUaTcpProtocolVersion;
  std::uint32_t receive_buffer_size = 65535;
  std::uint32_t send_buffer_size = 65535;
  std::uint32_t max_message_size = 0;  // 0 = no limit
  std::uint32_t max_chunk_count = 0;   // 0 = no limit
  std::string endpoint_url;

  friend bool operator==(const HelloMessage&, const HelloMessage&) = default;
};

// §7.1.2.4
struct AcknowledgeMessage {
  std::uint32_t protocol_version = kUaTcpProtocolVersion;
  std::uint32_t receive_buffer_size = 65535;
  std::uint32_t send_buffer_size = 65535;
  std::uint32_t max_message_size = 0;
  std::uint32_t max_chunk_count = 0;

  friend bool operator==(const AcknowledgeMessage&, const AcknowledgeMessage&) = default;
};

// §7.1.2.5
struct ErrorMessage {
  StatusCode error;
  std::string reason;

  friend bool operator==(const ErrorMessage&, const ErrorMessage&) = default;
};

// Whole messages, header included.
Bytes encode_hello(const HelloMessage& hello);
Bytes encode_acknowledge(const AcknowledgeMessage& ack);
Bytes encode_error(const ErrorMessage& error);
// Decode the body after the 8-byte header (exactly, trailing bytes are an error).
// BadDecodingError when malformed; an endpoint URL longer than 4096 bytes →
// BadTcpEndpointUrlInvalid.
Result<HelloMessage> decode_hello_body(ByteSpan body);
Result<AcknowledgeMessage> decode_acknowledge_body(ByteSpan body);
Result<ErrorMessage> decode_error_body(ByteSpan body);

// What one side is willing to use. Zero for max_message_size / max_chunk_count means
// "no limit" on the wire; locally the values below are enforced.
struct TransportLimits {
  std::uint32_t receive_buffer_size = 65535;
  std::uint32_t send_buffer_size = 65535;
  std::uint32_t max_message_size = 16U * 1024U * 1024U;
  std::uint32_t max_chunk_count = 1024;

  friend bool operator==(const TransportLimits&, const TransportLimits&) = default;
};

// The sizes both sides use after HEL/ACK, seen from one side.
struct NegotiatedLimits {
  std::uint32_t send_chunk_size = 0;      // largest chunk this side may send
  std::uint32_t receive_chunk_size = 0;   // largest chunk this side accepts
  std::uint32_t send_max_message = 0;     // the peer's maxMessageSize (0 = no limit)
  std::uint32_t send_max_chunks = 0;      // the peer's maxChunkCount (0 = no limit)
  std::uint32_t receive_max_message = 0;  // our own (0 = no limit)
  std::uint32_t receive_max_chunks = 0;   // our own (0 = no limit)

  friend bool operator==(const NegotiatedLimits&, const NegotiatedLimits&) = default;
};

// The Hello a client with `limits` sends.
HelloMessage make_hello(const TransportLimits& limits, std::string endpoint_url);

// Server side of §7.1.2.4: the ACK for `hello` given the server's own limits. The server's
// receive buffer is revised down to the client's send buffer and its send buffer to the
// client's receive buffer (never below 8192). A client buffer below 8192 →
// BadConnectionRejected. A newer client protocol version is accepted: the ACK carries ours.
Result<AcknowledgeMessage> negotiate_acknowledge(const HelloMessage& hello, const TransportLimits& server);
// The server's limits after it sent `ack` in answer to `hello`.
NegotiatedLimits server_limits(const HelloMessage& hello, const AcknowledgeMessage& ack);
// The client's limits after receiving `ack` to its `hello`. The server may not revise the
// client's buffers upward nor below 8192 → BadConnectionRejected.
Result<NegotiatedLimits> client_limits(const HelloMessage& hello, const AcknowledgeMessage& ack);

}  // namespace sf::opcua
