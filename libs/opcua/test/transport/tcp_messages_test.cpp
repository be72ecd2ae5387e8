#include "sf/opcua/transport/tcp_messages.hpp"

#include <gtest/gtest.h>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {
namespace {

Bytes hex(std::string_view text) {
  auto bytes = from_hex(text);
  EXPECT_TRUE(bytes.ok()) << text;
  return bytes.ok() ? *bytes : Bytes{};
}

// A Hello assembled by hand, field by field, from OPC 10000-6 Table 69 (not a capture): the
// shape node-opcua and UaExpert send — 64 KiB buffers, a 16 MiB message limit, a chunk limit —
// for the endpoint "opc.tcp://localhost:4840".
const std::string_view kHello =
    "48 45 4c 46"  // "HEL" 'F'
    "38 00 00 00"  // MessageSize 56
    "00 00 00 00"  // ProtocolVersion 0
    "00 00 01 00"  // ReceiveBufferSize 65536
    "00 00 01 00"  // SendBufferSize 65536
    "00 00 00 01"  // MaxMessageSize 16 MiB
    "88 13 00 00"  // MaxChunkCount 5000
    "18 00 00 00"  // EndpointUrl length 24
    "6f 70 63 2e 74 63 70 3a 2f 2f 6c 6f 63 61 6c 68 6f 73 74 3a 34 38 34 30";

TEST(TcpMessages, DecodesAHandAssembledHello) {
  const Bytes bytes = hex(kHello);
  auto header = decode_header(bytes);
  ASSERT_TRUE(header.ok()) << header.error().describe();
  EXPECT_EQ(header->type, MessageType::Hello);
  EXPECT_EQ(header->chunk, ChunkType::Final);
  EXPECT_EQ(header->size, bytes.size());
  auto hello = decode_hello_body(ByteSpan(bytes).subspan(8));
  ASSERT_TRUE(hello.ok()) << hello.error().describe();
  EXPECT_EQ(hello->protocol_version, 0U);
  EXPECT_EQ(hello->receive_buffer_size, 65536U);
  EXPECT_EQ(hello->send_buffer_size, 65536U);
  EXPECT_EQ(hello->max_message_size, 16U * 1024U * 1024U);
  EXPECT_EQ(hello->max_chunk_count, 5000U);
  EXPECT_EQ(hello->endpoint_url, "opc.tcp://localhost:4840");
  // And we encode exactly the same bytes.
  EXPECT_EQ(encode_hello(*hello), bytes);
}

TEST(TcpMessages, AcknowledgeAndErrorRoundTrip) {
  const AcknowledgeMessage ack{0, 8192, 65535, 0, 0};
  const Bytes a = encode_acknowledge(ack);
  EXPECT_EQ(a, hex("41434b46 1c000000 00000000 00200000 ffff0000 00000000 00000000"));
  auto decoded = decode_acknowledge_body(ByteSpan(a).subspan(8));
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(*decoded, ack);

  const ErrorMessage err{status::BadTcpMessageTooLarge, "too big"};
  const Bytes e = encode_error(err);
  EXPECT_EQ(e, hex("45525246 17000000 00008080 07000000 746f6f20626967"));
  auto decoded_err = decode_error_body(ByteSpan(e).subspan(8));
  ASSERT_TRUE(decoded_err.ok());
  EXPECT_EQ(*decoded_err, err);
}

TEST(TcpMessages, HelloRoundTripsWithNullUrl) {
  // A null EndpointUrl (length -1) decodes as empty.
  const Bytes bytes = hex("48454c46 20000000 00000000 00000100 00000100 00000000 00000000 ffffffff");
  auto hello = decode_hello_body(ByteSpan(bytes).subspan(8));
  ASSERT_TRUE(hello.ok()) << hello.error().describe();
  EXPECT_EQ(hello->endpoint_url, "");
}

TEST(TcpMessages, RejectsBadHeaders) {
  auto unknown = decode_header(hex("58595a46 08000000"));
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(status_of(unknown.error()), status::BadTcpMessageTypeInvalid);

  auto chunked_open = decode_header(hex("4f504e43 20000000"));  // OPN 'C'
  ASSERT_FALSE(chunked_open.ok());
  EXPECT_EQ(status_of(chunked_open.error()), status::BadTcpMessageTypeInvalid);

  auto bad_chunk = decode_header(hex("4d53475a 20000000"));  // MSG 'Z'
  ASSERT_FALSE(bad_chunk.ok());
  EXPECT_EQ(status_of(bad_chunk.error()), status::BadTcpMessageTypeInvalid);

  auto tiny = decode_header(hex("4d534746 04000000"));
  ASSERT_FALSE(tiny.ok());
  EXPECT_EQ(status_of(tiny.error()), status::BadDecodingError);

  auto ok = decode_header(hex("4d534743 20000000"));
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(ok->type, MessageType::SecureMessage);
  EXPECT_EQ(ok->chunk, ChunkType::Intermediate);
  auto abort = decode_header(hex("4d534741 20000000"));
  ASSERT_TRUE(abort.ok());
  EXPECT_EQ(abort->chunk, ChunkType::Abort);
}

TEST(TcpMessages, RejectsTooLongEndpointUrlAndTruncatedBodies) {
  HelloMessage hello;
  hello.endpoint_url = "opc.tcp://" + std::string(4100, 'a');
  const Bytes bytes = encode_hello(hello);
  auto decoded = decode_hello_body(ByteSpan(bytes).subspan(8));
  ASSERT_FALSE(decoded.ok());
  EXPECT_EQ(status_of(decoded.error()), status::BadTcpEndpointUrlInvalid);

  const Bytes truncated = hex("00000000 00000100 00000100");
  auto t = decode_hello_body(truncated);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(status_of(t.error()), status::BadDecodingError);

  const Bytes url_past_end = hex("00000000 00000100 00000100 00000000 00000000 10000000 6f70");
  auto p = decode_hello_body(url_past_end);
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(status_of(p.error()), status::BadDecodingError);

  const Bytes trailing = hex("00000000 00200000 00200000 00000000 00000000 00");
  auto a = decode_acknowledge_body(trailing);
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(status_of(a.error()), status::BadDecodingError);
}

TEST(TcpMessages, ServerRevisesBuffersDownToTheClients) {
  HelloMessage hello;
  hello.receive_buffer_size = 16384;
  hello.send_buffer_size = 8192;
  hello.max_message_size = 100000;
  hello.max_chunk_count = 10;
  TransportLimits server;  // 65535 / 65535, 16 MiB, 1024 chunks
  auto ack = negotiate_acknowledge(hello, server);
  ASSERT_TRUE(ack.ok());
  EXPECT_EQ(ack->receive_buffer_size, 8192U);  // ≤ the client's send buffer
  EXPECT_EQ(ack->send_buffer_size, 16384U);    // ≤ the client's receive buffer
  EXPECT_EQ(ack->max_message_size, server.max_message_size);
  EXPECT_EQ(ack->max_chunk_count, server.max_chunk_count);

  const NegotiatedLimits s = server_limits(hello, *ack);
  EXPECT_EQ(s.send_chunk_size, 16384U);
  EXPECT_EQ(s.receive_chunk_size, 8192U);
  EXPECT_EQ(s.send_max_message, 100000U);
  EXPECT_EQ(s.send_max_chunks, 10U);

  auto c = client_limits(hello, *ack);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->send_chunk_size, 8192U);
  EXPECT_EQ(c->receive_chunk_size, 16384U);
  EXPECT_EQ(c->send_max_message, server.max_message_size);
  EXPECT_EQ(c->receive_max_chunks, 10U);
}

TEST(TcpMessages, BuffersNeverGoBelow8192) {
  HelloMessage hello;
  hello.receive_buffer_size = 65536;
  hello.send_buffer_size = 65536;
  TransportLimits tiny;
  tiny.receive_buffer_size = 100;
  tiny.send_buffer_size = 100;
  auto ack = negotiate_acknowledge(hello, tiny);
  ASSERT_TRUE(ack.ok());
  EXPECT_EQ(ack->receive_buffer_size, 8192U);
  EXPECT_EQ(ack->send_buffer_size, 8192U);

  hello.receive_buffer_size = 4096;
  auto rejected = negotiate_acknowledge(hello, TransportLimits{});
  ASSERT_FALSE(rejected.ok());
  EXPECT_EQ(status_of(rejected.error()), status::BadConnectionRejected);

  EXPECT_EQ(make_hello(tiny, "opc.tcp://x").receive_buffer_size, 8192U);
}

TEST(TcpMessages, ClientRejectsAnAckThatRaisesItsBuffers) {
  HelloMessage hello;
  hello.receive_buffer_size = 8192;
  hello.send_buffer_size = 8192;
  AcknowledgeMessage ack{0, 65535, 8192, 0, 0};
  auto c = client_limits(hello, ack);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(status_of(c.error()), status::BadConnectionRejected);
}

}  // namespace
}  // namespace sf::opcua
