#include "sf/opcua/transport/secure_channel.hpp"

#include <gtest/gtest.h>

#include "channel_harness.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::test {
namespace {

using namespace std::chrono_literals;
using Kind = ChannelEvent::Kind;

TEST(SecureChannel, OpensWithHelloAcknowledgeAndOpen) {
  Harness h;
  h.open();
  EXPECT_EQ(h.client.channel_id(), 77U);
  EXPECT_EQ(h.server.channel_id(), 77U);
  EXPECT_EQ(h.client.token(), h.server.token());
  EXPECT_EQ(h.client.token().token_id, 1U);
  EXPECT_EQ(h.client.token().revised_lifetime, 60'000U);
  EXPECT_EQ(h.server.endpoint_url(), "opc.tcp://localhost:4840");
  EXPECT_EQ(h.server.security_policy_uri(), kSecurityPolicyNoneUri);
  EXPECT_EQ(h.server.security_mode(), MessageSecurityMode::None);
  EXPECT_EQ(count(h.client_events, Kind::Opened), 1U);
  EXPECT_EQ(count(h.server_events, Kind::Opened), 1U);
  EXPECT_EQ(h.client.negotiated_limits().send_chunk_size, 65535U);
}

TEST(SecureChannel, RequestAndResponse) {
  Harness h;
  h.open();
  auto id = h.client.send_request(read_request(7));
  ASSERT_TRUE(id.ok()) << id.error().describe();
  h.pump();
  const ChannelEvent* request = last(h.server_events, Kind::ServiceMessage);
  ASSERT_NE(request, nullptr);
  EXPECT_EQ(request->request_id, *id);
  ASSERT_TRUE(std::holds_alternative<ReadRequest>(*request->message));
  EXPECT_EQ(std::get<ReadRequest>(*request->message), read_request(7));

  ASSERT_TRUE(h.server.send_response(*id, read_response(7, 10)).ok());
  h.pump();
  const ChannelEvent* response = last(h.client_events, Kind::ServiceMessage);
  ASSERT_NE(response, nullptr);
  EXPECT_EQ(response->request_id, *id);
  ASSERT_TRUE(std::holds_alternative<ReadResponse>(*response->message));
  EXPECT_EQ(std::get<ReadResponse>(*response->message), read_response(7, 10));
}

TEST(SecureChannel, LargeMessagesAreSplitIntoChunksAndReassembled) {
  Harness h;
  h.open();
  auto id = h.client.send_request(read_request(1, 5000));  // ~100 KB: several 64 KiB chunks
  ASSERT_TRUE(id.ok());
  const Bytes request_bytes = h.client.take_output();
  const auto request_chunks = split_chunks(request_bytes);
  ASSERT_GT(request_chunks.size(), 1U);
  for (std::size_t i = 0; i < request_chunks.size(); ++i) {
    EXPECT_LE(request_chunks[i].first.size, 65535U);
    EXPECT_EQ(request_chunks[i].first.chunk,
              i + 1 == request_chunks.size() ? ChunkType::Final : ChunkType::Intermediate);
  }
  h.server.receive(request_bytes);
  h.pump();
  ASSERT_NE(last(h.server_events, Kind::ServiceMessage), nullptr);
  EXPECT_EQ(std::get<ReadRequest>(*last(h.server_events, Kind::ServiceMessage)->message),
            read_request(1, 5000));

  ASSERT_TRUE(h.server.send_response(*id, read_response(1, 3'000'000)).ok());
  h.pump();
  EXPECT_GE(split_chunks(h.server_sent).size(), 45U);  // 3 MB / 64 KiB
  const ChannelEvent* response = last(h.client_events, Kind::ServiceMessage);
  ASSERT_NE(response, nullptr);
  EXPECT_EQ(std::get<ReadResponse>(*response->message), read_response(1, 3'000'000));
}

TEST(SecureChannel, BytesMayArriveInAnySplit) {
  Harness h;
  h.client.start();
  // Feed everything one byte at a time.
  for (int round = 0; round < 10; ++round) {
    for (const std::uint8_t b : h.client.take_output()) {
      h.server.receive(ByteSpan(&b, 1));
    }
    for (const std::uint8_t b : h.server.take_output()) {
      h.client.receive(ByteSpan(&b, 1));
    }
  }
  EXPECT_TRUE(h.client.is_open());
  EXPECT_TRUE(h.server.is_open());
}

TEST(SecureChannel, AbortChunkDropsThePartialMessage) {
  Harness h;
  h.open();
  const Bytes body = body_of(read_request(3));
  h.server.receive(raw_chunk("MSG", 'C', 77, 1, 2, 9, ByteSpan(body).first(10)));
  ByteWriter abort_body;
  abort_body.u32(status::BadRequestTooLarge.value());
  Encoder e(abort_body);
  encode_binary(e, String("request too large"));
  h.server.receive(raw_chunk("MSG", 'A', 77, 1, 3, 9, abort_body.data()));
  h.collect();
  const ChannelEvent* aborted = last(h.server_events, Kind::Aborted);
  ASSERT_NE(aborted, nullptr);
  EXPECT_EQ(aborted->request_id, 9U);
  EXPECT_EQ(aborted->status, status::BadRequestTooLarge);
  EXPECT_EQ(aborted->reason, "request too large");
  EXPECT_EQ(count(h.server_events, Kind::ServiceMessage), 0U);
  EXPECT_TRUE(h.server.is_open());
  // The channel goes on: a whole message afterwards is delivered.
  h.server.receive(raw_chunk("MSG", 'F', 77, 1, 4, 10, body));
  h.collect();
  ASSERT_NE(last(h.server_events, Kind::ServiceMessage), nullptr);
  EXPECT_EQ(last(h.server_events, Kind::ServiceMessage)->request_id, 10U);
}

TEST(SecureChannel, ClientReportsAbortedResponses) {
  Harness h;
  h.open();
  auto id = h.client.send_request(read_request(3));
  ASSERT_TRUE(id.ok());
  h.pump();
  ByteWriter abort_body;
  abort_body.u32(status::BadResponseTooLarge.value());
  abort_body.i32(-1);
  // The server's first symmetric chunk after its OPN response carries sequence number 2.
  h.client.receive(raw_chunk("MSG", 'A', 77, 1, 2, *id, abort_body.data()));
  h.collect();
  const ChannelEvent* aborted = last(h.client_events, Kind::Aborted);
  ASSERT_NE(aborted, nullptr);
  EXPECT_EQ(aborted->request_id, *id);
  EXPECT_EQ(aborted->status, status::BadResponseTooLarge);
}

// ---- limits and violations → ERR + closed ----------------------------------------------------

TEST(SecureChannel, MessageLargerThanMaxMessageSize) {
  SecureChannelConfig s = server_config();
  s.limits.max_message_size = 10'000;
  Harness h(client_config(), s);
  h.open();
  // The client knows the server's limit and refuses to send.
  auto refused = h.client.send_request(read_request(1, 2000));
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(status_of(refused.error()), status::BadRequestTooLarge);
  EXPECT_FALSE(h.client.has_output());
  // A peer that sends anyway is cut off.
  const Bytes piece(6000, 0);
  h.server.receive(raw_chunk("MSG", 'C', 77, 1, 2, 5, piece));
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'C', 77, 1, 3, 5, piece)).error, status::BadTcpMessageTooLarge);
}

TEST(SecureChannel, TooManyChunks) {
  SecureChannelConfig s = server_config();
  s.limits.max_chunk_count = 3;
  Harness h(client_config(), s);
  h.open();
  const Bytes piece(100, 0);
  for (std::uint32_t i = 0; i < 3; ++i) {
    h.server.receive(raw_chunk("MSG", 'C', 77, 1, 2 + i, 5, piece));
  }
  EXPECT_TRUE(h.server.is_open());
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'C', 77, 1, 5, 5, piece)).error,
            status::BadEncodingLimitsExceeded);
}

TEST(SecureChannel, ChunkLargerThanTheReceiveBuffer) {
  SecureChannelConfig s = server_config();
  s.limits.receive_buffer_size = 8192;
  Harness h(client_config(), s);
  h.open();
  // Only the header is needed to reject it.
  Bytes header = raw_chunk("MSG", 'F', 77, 1, 2, 5, {});
  store_le<std::uint32_t>(header.data() + 4, 8193);
  EXPECT_EQ(h.server_rejects(header).error, status::BadTcpMessageTooLarge);
}

TEST(SecureChannel, BadSequenceNumber) {
  Harness h;
  h.open();
  const Bytes body = body_of(read_request(3));
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'F', 77, 1, 5, 5, body)).error,
            status::BadSequenceNumberInvalid);
}

TEST(SecureChannel, UnknownToken) {
  Harness h;
  h.open();
  const Bytes body = body_of(read_request(3));
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'F', 77, 42, 2, 5, body)).error,
            status::BadSecureChannelTokenUnknown);
}

TEST(SecureChannel, WrongChannelId) {
  Harness h;
  h.open();
  const Bytes body = body_of(read_request(3));
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'F', 78, 1, 2, 5, body)).error,
            status::BadTcpSecureChannelUnknown);
}

TEST(SecureChannel, UnknownSecurityPolicy) {
  Harness h;
  h.server.receive(encode_hello(make_hello(TransportLimits{}, "opc.tcp://x")));
  (void)h.server.take_output();
  const auto request = open_request(SecurityTokenRequestType::Issue);
  const ErrorMessage err = h.server_rejects(
      raw_open(0, "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256", 1, 1, request));
  EXPECT_EQ(err.error, status::BadSecurityPolicyRejected);
  EXPECT_NE(err.reason.find("Basic256Sha256"), std::string::npos);
}

TEST(SecureChannel, GarbageHeader) {
  Harness h;
  const std::string garbage = "GET / HTTP/1.1\r\n\r\n";
  EXPECT_EQ(
      h.server_rejects(ByteSpan(reinterpret_cast<const std::uint8_t*>(garbage.data()), garbage.size())).error,
      status::BadTcpMessageTypeInvalid);
}

TEST(SecureChannel, MessageBeforeOpen) {
  Harness h;
  h.server.receive(encode_hello(make_hello(TransportLimits{}, "opc.tcp://x")));
  (void)h.server.take_output();
  const Bytes body = body_of(read_request(3));
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'F', 0, 0, 1, 1, body)).error,
            status::BadTcpSecureChannelUnknown);
}

TEST(SecureChannel, OpenBeforeHello) {
  Harness h;
  EXPECT_EQ(h.server_rejects(
                 raw_open(0, kSecurityPolicyNoneUri, 1, 1, open_request(SecurityTokenRequestType::Issue)))
                .error,
            status::BadTcpMessageTypeInvalid);
}

TEST(SecureChannel, FirstOpenWithAChannelId) {
  Harness h;
  h.server.receive(encode_hello(make_hello(TransportLimits{}, "opc.tcp://x")));
  (void)h.server.take_output();
  EXPECT_EQ(h.server_rejects(
                 raw_open(5, kSecurityPolicyNoneUri, 1, 1, open_request(SecurityTokenRequestType::Issue)))
                .error,
            status::BadTcpSecureChannelUnknown);
}

TEST(SecureChannel, RenewBeforeIssue) {
  Harness h;
  h.server.receive(encode_hello(make_hello(TransportLimits{}, "opc.tcp://x")));
  (void)h.server.take_output();
  EXPECT_EQ(h.server_rejects(
                 raw_open(0, kSecurityPolicyNoneUri, 1, 1, open_request(SecurityTokenRequestType::Renew)))
                .error,
            status::BadRequestTypeInvalid);
}

TEST(SecureChannel, SecurityModeMustMatchThePolicy) {
  Harness h;
  h.server.receive(encode_hello(make_hello(TransportLimits{}, "opc.tcp://x")));
  (void)h.server.take_output();
  auto request = open_request(SecurityTokenRequestType::Issue);
  request.security_mode = MessageSecurityMode::SignAndEncrypt;
  EXPECT_EQ(h.server_rejects(raw_open(0, kSecurityPolicyNoneUri, 1, 1, request)).error,
            status::BadSecurityModeRejected);
}

TEST(SecureChannel, HelloWithTooSmallBuffers) {
  Harness h;
  HelloMessage hello = make_hello(TransportLimits{}, "opc.tcp://x");
  hello.receive_buffer_size = 1024;
  EXPECT_EQ(h.server_rejects(encode_hello(hello)).error, status::BadConnectionRejected);
}

TEST(SecureChannel, SecondHello) {
  Harness h;
  h.open();
  EXPECT_EQ(h.server_rejects(encode_hello(make_hello(TransportLimits{}, "opc.tcp://x"))).error,
            status::BadTcpMessageTypeInvalid);
}

TEST(SecureChannel, ClientClosesOnServerError) {
  Harness h;
  h.open();
  h.client.receive(encode_error(ErrorMessage{status::BadTcpServerTooBusy, "busy"}));
  h.collect();
  EXPECT_TRUE(h.client.is_closed());
  const ChannelEvent* closed = last(h.client_events, Kind::Closed);
  ASSERT_NE(closed, nullptr);
  EXPECT_EQ(closed->status, status::BadTcpServerTooBusy);
  EXPECT_EQ(closed->reason, "busy");
}

TEST(SecureChannel, ServerRejectedHelloReachesTheClient) {
  SecureChannelConfig c = client_config();
  c.endpoint_url = "opc.tcp://" + std::string(5000, 'x');
  Harness h(c, server_config());
  h.client.start();
  h.pump();
  EXPECT_TRUE(h.client.is_closed());
  ASSERT_NE(last(h.client_events, Kind::Closed), nullptr);
  EXPECT_EQ(last(h.client_events, Kind::Closed)->status, status::BadTcpEndpointUrlInvalid);
}

// ---- undecodable requests → the owner answers a ServiceFault ---------------------------------

TEST(SecureChannel, UnknownServiceIsReportedWithTheRequestHandle) {
  Harness h;
  h.open();
  ByteWriter body;
  Encoder e(body);
  encode_binary(e, NodeId(0, 615));  // QueryFirstRequest_Encoding_DefaultBinary: not in our schema
  RequestHeader header;
  header.request_handle = 4711;
  encode_binary(e, header);
  body.u32(0);  // whatever follows
  h.server.receive(raw_chunk("MSG", 'F', 77, 1, 2, 12, body.data()));
  h.collect();
  const ChannelEvent* event = last(h.server_events, Kind::Undecodable);
  ASSERT_NE(event, nullptr);
  EXPECT_EQ(event->request_id, 12U);
  EXPECT_EQ(event->status, status::BadServiceUnsupported);
  EXPECT_EQ(event->request_handle, 4711U);
  EXPECT_TRUE(h.server.is_open());
}

TEST(SecureChannel, ResponseTypesAreNotServiceRequests) {
  Harness h;
  h.open();
  h.server.receive(raw_chunk("MSG", 'F', 77, 1, 2, 12, body_of(read_response(5))));
  h.collect();
  const ChannelEvent* event = last(h.server_events, Kind::Undecodable);
  ASSERT_NE(event, nullptr);
  EXPECT_EQ(event->status, status::BadServiceUnsupported);
}

TEST(SecureChannel, MalformedRequestIsADecodingError) {
  Harness h;
  h.open();
  Bytes body = body_of(read_request(99, 3));
  body.resize(body.size() - 5);
  h.server.receive(raw_chunk("MSG", 'F', 77, 1, 2, 13, body));
  h.collect();
  const ChannelEvent* event = last(h.server_events, Kind::Undecodable);
  ASSERT_NE(event, nullptr);
  EXPECT_EQ(event->status, status::BadDecodingError);
  EXPECT_EQ(event->request_handle, 99U);
  EXPECT_TRUE(h.server.is_open());
}

TEST(SecureChannel, ResponseTooLargeForTheClientBecomesAServiceFault) {
  SecureChannelConfig c = client_config();
  c.limits.max_message_size = 50'000;
  Harness h(c, server_config());
  h.open();
  auto id = h.client.send_request(read_request(31));
  ASSERT_TRUE(id.ok());
  h.pump();
  ASSERT_TRUE(h.server.send_response(*id, read_response(31, 100'000)).ok());
  h.pump();
  const ChannelEvent* response = last(h.client_events, Kind::ServiceMessage);
  ASSERT_NE(response, nullptr);
  ASSERT_TRUE(std::holds_alternative<ServiceFault>(*response->message));
  const auto& fault = std::get<ServiceFault>(*response->message);
  EXPECT_EQ(fault.response_header.service_result, status::BadResponseTooLarge);
  EXPECT_EQ(fault.response_header.request_handle, 31U);
  EXPECT_TRUE(h.client.is_open());
}

// ---- close, tokens, sequence numbers ---------------------------------------------------------

TEST(SecureChannel, ClientCloseSendsClo) {
  Harness h;
  h.open();
  h.client.close();
  const Bytes out = h.client.take_output();
  const auto chunks = split_chunks(out);
  ASSERT_EQ(chunks.size(), 1U);
  EXPECT_EQ(chunks[0].first.type, MessageType::CloseSecureChannel);
  h.server.receive(out);
  h.collect();
  EXPECT_TRUE(h.server.is_closed());
  EXPECT_FALSE(h.server.has_output());  // no answer to CLO
  ASSERT_NE(last(h.server_events, Kind::Closed), nullptr);
  EXPECT_EQ(last(h.server_events, Kind::Closed)->status, status::Good);
  EXPECT_EQ(last(h.client_events, Kind::Closed)->status, status::Good);
  EXPECT_FALSE(h.client.send_request(read_request(1)).ok());
}

TEST(SecureChannel, RevisedLifetimeIsClamped) {
  SecureChannelConfig c = client_config();
  c.requested_lifetime_ms = 1000;
  Harness low(c, server_config());
  low.open();
  EXPECT_EQ(low.client.token().revised_lifetime, 10'000U);

  c.requested_lifetime_ms = 36'000'000;
  Harness high(c, server_config());
  high.open();
  EXPECT_EQ(high.client.token().revised_lifetime, 3'600'000U);
}

TEST(SecureChannel, ClientRenewsAt75PercentAndTheOldTokenOverlaps) {
  Harness h;  // lifetime 60 s
  h.open();
  ASSERT_TRUE(h.client.next_deadline().has_value());
  EXPECT_EQ(*h.client.next_deadline() - h.clock.now(), 45s);
  h.clock.advance(44s);
  h.client.on_timer();
  EXPECT_FALSE(h.client.has_output());
  h.clock.advance(1s);
  h.client.on_timer();
  h.pump();
  EXPECT_EQ(count(h.client_events, Kind::Renewed), 1U);
  EXPECT_EQ(count(h.server_events, Kind::Renewed), 1U);
  EXPECT_EQ(h.client.token().token_id, 2U);
  EXPECT_EQ(h.server.token().token_id, 2U);
  EXPECT_EQ(h.client.token().channel_id, 77U);

  // A request the client secured with the old token before it saw the renewal is accepted
  // (client sequence numbers so far: 1 OPN Issue, 2 OPN Renew).
  h.server.receive(raw_chunk("MSG", 'F', 77, 1, 3, 50, body_of(read_request(1))));
  h.collect();
  ASSERT_NE(last(h.server_events, Kind::ServiceMessage), nullptr);
  // Until the client uses the new token, the server answers with the old one.
  ASSERT_TRUE(h.server.send_response(50, read_response(1)).ok());
  auto answer = split_chunks(h.server.take_output());
  ASSERT_EQ(answer.size(), 1U);
  EXPECT_EQ(token_of(answer[0].second), 1U);
  // The client accepts it.
  h.client.receive(answer[0].second);
  h.collect();
  EXPECT_TRUE(h.client.is_open());

  // Now the client uses token 2; afterwards token 1 is gone.
  h.server.receive(raw_chunk("MSG", 'F', 77, 2, 4, 51, body_of(read_request(2))));
  ASSERT_TRUE(h.server.send_response(51, read_response(2)).ok());
  answer = split_chunks(h.server.take_output());
  ASSERT_EQ(answer.size(), 1U);
  EXPECT_EQ(token_of(answer[0].second), 2U);
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'F', 77, 1, 5, 52, body_of(read_request(3)))).error,
            status::BadSecureChannelTokenUnknown);
}

TEST(SecureChannel, OldTokenOverlapEndsAfterAQuarterOfItsLifetime) {
  Harness h;
  h.open();
  h.clock.advance(45s);
  h.client.on_timer();
  h.pump();
  ASSERT_EQ(h.server.token().token_id, 2U);
  // The old token would have expired at 60 s; 25 % of 60 s after the renewal is also 60 s.
  h.clock.advance(15s);
  h.server.on_timer();
  EXPECT_TRUE(h.server.is_open());
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'F', 77, 1, 3, 50, body_of(read_request(1)))).error,
            status::BadSecureChannelTokenUnknown);
}

TEST(SecureChannel, ServerClosesWhenTheTokenExpiresWithoutRenewal) {
  Harness h;
  h.open();
  ASSERT_TRUE(h.server.next_deadline().has_value());
  EXPECT_EQ(*h.server.next_deadline() - h.clock.now(), 60s);
  h.clock.advance(59s);
  h.server.on_timer();
  EXPECT_TRUE(h.server.is_open());
  h.clock.advance(1s);
  h.server.on_timer();
  EXPECT_TRUE(h.server.is_closed());
  const Bytes out = h.server.take_output();
  auto header = decode_header(out);
  ASSERT_TRUE(header.ok());
  EXPECT_EQ(header->type, MessageType::Error);
  auto err = decode_error_body(ByteSpan(out).subspan(8));
  ASSERT_TRUE(err.ok());
  EXPECT_EQ(err->error, status::BadSecureChannelTokenUnknown);
}

TEST(SecureChannel, ClientGivesUpWhenRenewalIsNeverAnswered) {
  Harness h;
  h.open();
  h.clock.advance(45s);
  h.client.on_timer();  // OPN Renew, never delivered
  (void)h.client.take_output();
  h.clock.advance(29s);
  h.client.on_timer();
  EXPECT_TRUE(h.client.is_open());
  h.clock.advance(1s);  // 60 s + 25 %
  h.client.on_timer();
  h.collect();
  EXPECT_TRUE(h.client.is_closed());
  EXPECT_EQ(last(h.client_events, Kind::Closed)->status, status::BadSecureChannelClosed);
}

TEST(SecureChannel, RenewedChannelKeepsWorkingAcrossManyRenewals) {
  Harness h;
  h.open();
  for (std::uint32_t i = 0; i < 5; ++i) {
    h.clock.advance(45s);
    h.client.on_timer();
    h.pump();
    auto id = h.client.send_request(read_request(i));
    ASSERT_TRUE(id.ok());
    h.pump();
    ASSERT_TRUE(h.server.send_response(*id, read_response(i)).ok());
    h.pump();
    ASSERT_TRUE(h.client.is_open());
    ASSERT_TRUE(h.server.is_open());
  }
  EXPECT_EQ(h.client.token().token_id, 6U);
  EXPECT_EQ(count(h.client_events, Kind::ServiceMessage), 5U);
}

TEST(SecureChannel, SequenceNumbersWrapAroundPerSpec) {
  SecureChannelConfig c = client_config();
  c.first_sequence_number = UINT32_MAX - 2;
  SecureChannelConfig s = server_config();
  s.first_sequence_number = UINT32_MAX - 1;
  Harness h(c, s);
  h.open();
  for (std::uint32_t i = 0; i < 6; ++i) {
    auto id = h.client.send_request(read_request(i));
    ASSERT_TRUE(id.ok());
    h.pump();
    ASSERT_TRUE(h.server.send_response(*id, read_response(i)).ok());
    h.pump();
  }
  EXPECT_TRUE(h.client.is_open());
  EXPECT_TRUE(h.server.is_open());
  EXPECT_EQ(count(h.client_events, Kind::ServiceMessage), 6U);
}

TEST(SecureChannel, WrapToALargeNumberIsRejected) {
  SecureChannelConfig c = client_config();
  c.first_sequence_number = UINT32_MAX;
  Harness h(c, server_config());
  h.open();  // OPN used UINT32_MAX
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'F', 77, 1, 5000, 2, body_of(read_request(1)))).error,
            status::BadSequenceNumberInvalid);
}

TEST(SecureChannel, InterleavedMessagesAreRejected) {
  Harness h;
  h.open();
  const Bytes piece(10, 0);
  h.server.receive(raw_chunk("MSG", 'C', 77, 1, 2, 5, piece));
  EXPECT_EQ(h.server_rejects(raw_chunk("MSG", 'C', 77, 1, 3, 6, piece)).error,
            status::BadTcpMessageTypeInvalid);
}

}  // namespace
}  // namespace sf::opcua::test
