#include "sf/opcua/transport/tcp_messages.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {
namespace {

constexpr std::array<std::string_view, 7> kTypeNames = {"HEL", "ACK", "ERR", "RHE", "OPN", "MSG", "CLO"};

// Writes the header with a size placeholder; patch_size() fills it in at the end.
void begin(ByteWriter& w, MessageType type) {
  encode_header(w, MessageHeader{type, ChunkType::Final, 0});
}

Bytes finish(ByteWriter& w) {
  (void)w.patch<std::uint32_t>(4, static_cast<std::uint32_t>(w.size()));
  return w.take();
}

// A UA-TCP String (§7.1.2.3 uses the OPC UA String encoding: Int32 length, -1 = null).
void write_string(ByteWriter& w, std::string_view s) {
  w.i32(static_cast<std::int32_t>(s.size()));
  w.bytes(ByteSpan(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));  // NOLINT
}

bool read_string(ByteReader& r, std::string& out, std::size_t max) {
  const std::int32_t length = r.i32();
  if (!r.ok() || length < -1) {
    r.fail();
    return false;
  }
  if (length <= 0) {
    out.clear();
    return true;
  }
  if (static_cast<std::size_t>(length) > max) {
    return false;  // reader still ok: the caller reports "too long"
  }
  if (static_cast<std::size_t>(length) > r.remaining()) {
    r.fail();
    return false;
  }
  const auto bytes = r.bytes(static_cast<std::size_t>(length));
  out.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());  // NOLINT
  return r.ok();
}

Status check_end(const ByteReader& r, std::string_view what) {
  if (!r.ok()) {
    return status_error(status::BadDecodingError, fmt::format("{} message truncated", what));
  }
  if (!r.at_end()) {
    return status_error(status::BadDecodingError,
                        fmt::format("{} message has {} trailing bytes", what, r.remaining()));
  }
  return {};
}

}  // namespace

std::string_view to_string(MessageType type) {
  return kTypeNames.at(static_cast<std::size_t>(type));
}

std::optional<MessageType> message_type_from(ByteSpan three_bytes) {
  if (three_bytes.size() < 3) {
    return std::nullopt;
  }
  const std::string_view text(reinterpret_cast<const char*>(three_bytes.data()), 3);  // NOLINT
  for (std::size_t i = 0; i < kTypeNames.size(); ++i) {
    if (kTypeNames[i] == text) {
      return static_cast<MessageType>(i);
    }
  }
  return std::nullopt;
}

void encode_header(ByteWriter& w, const MessageHeader& header) {
  const auto name = to_string(header.type);
  for (const char c : name) {
    w.u8(static_cast<std::uint8_t>(c));
  }
  w.u8(static_cast<std::uint8_t>(header.chunk));
  w.u32(header.size);
}

Result<MessageHeader> decode_header(ByteSpan bytes) {
  if (bytes.size() < kMessageHeaderSize) {
    return status_error(status::BadDecodingError,
                        fmt::format("message header needs 8 bytes, got {}", bytes.size()));
  }
  const auto type = message_type_from(bytes.first(3));
  if (!type) {
    return status_error(status::BadTcpMessageTypeInvalid,
                        fmt::format("unknown message type {}", to_hex(bytes.first(3))));
  }
  MessageHeader header;
  header.type = *type;
  const std::uint8_t chunk = bytes[3];
  const bool connection_protocol = *type == MessageType::Hello || *type == MessageType::Acknowledge ||
                                   *type == MessageType::Error || *type == MessageType::ReverseHello;
  // §7.1.2.2: the byte is ignored for HEL/ACK/ERR/RHE. §6.7.2.2: only MSG may be split or
  // aborted; OPN and CLO are always 'F'.
  if (connection_protocol || chunk == 'F') {
    header.chunk = ChunkType::Final;
  } else if ((chunk == 'C' || chunk == 'A') && *type == MessageType::SecureMessage) {
    header.chunk = static_cast<ChunkType>(chunk);
  } else {
    return status_error(status::BadTcpMessageTypeInvalid,
                        fmt::format("chunk type 0x{:02x} invalid for {}", chunk, to_string(*type)));
  }
  header.size = load_le<std::uint32_t>(bytes.data() + 4);
  if (header.size < kMessageHeaderSize) {
    return status_error(status::BadDecodingError, fmt::format("{} message size {} is below the header size",
                                                              to_string(*type), header.size));
  }
  return header;
}

Bytes encode_hello(const HelloMessage& hello) {
  ByteWriter w;
  begin(w, MessageType::Hello);
  w.u32(hello.protocol_version);
  w.u32(hello.receive_buffer_size);
  w.u32(hello.send_buffer_size);
  w.u32(hello.max_message_size);
  w.u32(hello.max_chunk_count);
  write_string(w, hello.endpoint_url);
  return finish(w);
}

Bytes encode_acknowledge(const AcknowledgeMessage& ack) {
  ByteWriter w;
  begin(w, MessageType::Acknowledge);
  w.u32(ack.protocol_version);
  w.u32(ack.receive_buffer_size);
  w.u32(ack.send_buffer_size);
  w.u32(ack.max_message_size);
  w.u32(ack.max_chunk_count);
  return finish(w);
}

Bytes encode_error(const ErrorMessage& error) {
  ByteWriter w;
  begin(w, MessageType::Error);
  w.u32(error.error.value());
  // §7.1.2.5: the reason is at most 4096 bytes.
  write_string(w, std::string_view(error.reason).substr(0, 4096));
  return finish(w);
}

Result<HelloMessage> decode_hello_body(ByteSpan body) {
  ByteReader r(body);
  HelloMessage hello;
  hello.protocol_version = r.u32();
  hello.receive_buffer_size = r.u32();
  hello.send_buffer_size = r.u32();
  hello.max_message_size = r.u32();
  hello.max_chunk_count = r.u32();
  if (!read_string(r, hello.endpoint_url, kMaxEndpointUrlLength) && r.ok()) {
    return status_error(status::BadTcpEndpointUrlInvalid, "HEL endpoint URL longer than 4096 bytes");
  }
  SF_TRY(check_end(r, "HEL"));
  return hello;
}

Result<AcknowledgeMessage> decode_acknowledge_body(ByteSpan body) {
  ByteReader r(body);
  AcknowledgeMessage ack;
  ack.protocol_version = r.u32();
  ack.receive_buffer_size = r.u32();
  ack.send_buffer_size = r.u32();
  ack.max_message_size = r.u32();
  ack.max_chunk_count = r.u32();
  SF_TRY(check_end(r, "ACK"));
  return ack;
}

Result<ErrorMessage> decode_error_body(ByteSpan body) {
  ByteReader r(body);
  ErrorMessage error;
  error.error = StatusCode(r.u32());
  if (!read_string(r, error.reason, 1U << 20U) && r.ok()) {
    return status_error(status::BadDecodingError, "ERR reason longer than 1 MiB");
  }
  SF_TRY(check_end(r, "ERR"));
  return error;
}

HelloMessage make_hello(const TransportLimits& limits, std::string endpoint_url) {
  HelloMessage hello;
  hello.receive_buffer_size = std::max(limits.receive_buffer_size, kMinBufferSize);
  hello.send_buffer_size = std::max(limits.send_buffer_size, kMinBufferSize);
  hello.max_message_size = limits.max_message_size;
  hello.max_chunk_count = limits.max_chunk_count;
  hello.endpoint_url = std::move(endpoint_url);
  return hello;
}

Result<AcknowledgeMessage> negotiate_acknowledge(const HelloMessage& hello, const TransportLimits& server) {
  // §7.1.2.3: both buffers are at least 8192 bytes.
  if (hello.receive_buffer_size < kMinBufferSize || hello.send_buffer_size < kMinBufferSize) {
    return status_error(
        status::BadConnectionRejected,
        fmt::format("HEL buffer sizes {}/{} below 8192", hello.receive_buffer_size, hello.send_buffer_size));
  }
  AcknowledgeMessage ack;
  ack.protocol_version = kUaTcpProtocolVersion;
  // §7.1.2.4: the server's receive buffer shall not be larger than the client's send buffer,
  // its send buffer not larger than the client's receive buffer.
  ack.receive_buffer_size =
      std::min(std::max(server.receive_buffer_size, kMinBufferSize), hello.send_buffer_size);
  ack.send_buffer_size =
      std::min(std::max(server.send_buffer_size, kMinBufferSize), hello.receive_buffer_size);
  ack.max_message_size = server.max_message_size;
  ack.max_chunk_count = server.max_chunk_count;
  return ack;
}

NegotiatedLimits server_limits(const HelloMessage& hello, const AcknowledgeMessage& ack) {
  NegotiatedLimits n;
  n.send_chunk_size = ack.send_buffer_size;
  n.receive_chunk_size = ack.receive_buffer_size;
  n.send_max_message = hello.max_message_size;
  n.send_max_chunks = hello.max_chunk_count;
  n.receive_max_message = ack.max_message_size;
  n.receive_max_chunks = ack.max_chunk_count;
  return n;
}

Result<NegotiatedLimits> client_limits(const HelloMessage& hello, const AcknowledgeMessage& ack) {
  if (ack.receive_buffer_size < kMinBufferSize || ack.send_buffer_size < kMinBufferSize) {
    return status_error(
        status::BadConnectionRejected,
        fmt::format("ACK buffer sizes {}/{} below 8192", ack.receive_buffer_size, ack.send_buffer_size));
  }
  if (ack.receive_buffer_size > hello.send_buffer_size || ack.send_buffer_size > hello.receive_buffer_size) {
    return status_error(status::BadConnectionRejected,
                        fmt::format("ACK buffer sizes {}/{} exceed the HEL's {}/{}", ack.receive_buffer_size,
                                    ack.send_buffer_size, hello.send_buffer_size, hello.receive_buffer_size));
  }
  NegotiatedLimits n;
  // The client sends chunks the server can receive and receives chunks the server sends.
  n.send_chunk_size = ack.receive_buffer_size;
  n.receive_chunk_size = hello.receive_buffer_size;
  n.send_max_message = ack.max_message_size;
  n.send_max_chunks = ack.max_chunk_count;
  n.receive_max_message = hello.max_message_size;
  n.receive_max_chunks = hello.max_chunk_count;
  return n;
}

}  // namespace sf::opcua
