// Laying out, securing and opening one secure-conversation chunk (OPC 10000-6 §6.7.2), and
// small helpers over Message. Internal to sf_opcua_transport.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/messages.hpp"
#include "sf/opcua/transport/security_policy.hpp"
#include "sf/opcua/transport/tcp_messages.hpp"

namespace sf::opcua::detail {

// MessageHeader (8) + SecureChannelId (4).
inline constexpr std::size_t kSecureHeaderSize = 12;
// SequenceNumber + RequestId (§6.7.2.4).
inline constexpr std::size_t kSequenceHeaderSize = 8;
// §6.7.2.4: sequence numbers wrap only after exceeding UInt32.MaxValue - 1024; the first
// number after the wrap is below 1024.
inline constexpr std::uint32_t kSequenceWrapThreshold = 4'294'966'271U;
inline constexpr std::uint32_t kSequenceWrapLimit = 1024;

struct ChunkSpec {
  MessageType type = MessageType::SecureMessage;
  ChunkType chunk = ChunkType::Final;
  std::uint32_t channel_id = 0;
  ByteSpan security_header;  // asymmetric header, or the 4-byte TokenId
  std::uint32_t sequence_number = 0;
  std::uint32_t request_id = 0;
  ByteSpan body;
};

// The largest body that fits a chunk of chunk_size bytes with this security header size (all
// bytes before the sequence header) and crypto; 0 when not even one byte fits.
std::size_t max_body_size(std::uint32_t chunk_size, std::size_t header_size, const MessageCrypto& crypto);

// Lays out, pads, signs and encrypts one chunk and appends it to out.
Status append_chunk(Bytes& out, const ChunkSpec& spec, const MessageCrypto& crypto);

// Decrypts and verifies a received chunk whose headers take header_size bytes, strips padding
// and signature, and returns the plaintext from the sequence header to the end of the body
// (a view into chunk or into scratch). BadSecurityChecksFailed when anything does not fit.
Result<ByteSpan> open_chunk(ByteSpan chunk, std::size_t header_size, const MessageCrypto& crypto,
                            Bytes& scratch);

// The message of an error without its leading "BadXxx: " (for ERR reasons and logs, which
// carry the StatusCode separately).
std::string reason_of(const Error& error);

// True for the service requests (alternatives with a RequestHeader).
bool is_request(const Message& message);
// The requestHandle of a request's or response's header.
std::uint32_t request_handle_of(const Message& message);

}  // namespace sf::opcua::detail
