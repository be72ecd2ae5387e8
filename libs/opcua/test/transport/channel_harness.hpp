// A client and a server SecureChannel wired together in memory, plus raw-chunk builders for
// feeding hand-made (and broken) input to one side.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/opcua/encoding.hpp"
#include "sf/opcua/transport/secure_channel.hpp"

namespace sf::opcua::test {

inline SecureChannelConfig server_config() {
  SecureChannelConfig c;
  c.role = ChannelRole::Server;
  c.channel_id = 77;
  return c;
}

inline SecureChannelConfig client_config() {
  SecureChannelConfig c;
  c.role = ChannelRole::Client;
  c.endpoint_url = "opc.tcp://localhost:4840";
  c.requested_lifetime_ms = 60'000;
  return c;
}

inline ReadRequest read_request(std::uint32_t handle, std::size_t nodes = 1) {
  ReadRequest r;
  r.request_header.request_handle = handle;
  r.request_header.timeout_hint = 1000;
  std::vector<ReadValueId> ids(nodes);
  for (std::size_t i = 0; i < nodes; ++i) {
    ids[i].node_id = NodeId(2, static_cast<std::uint32_t>(1000 + i));
    ids[i].attribute_id = 13;
  }
  r.nodes_to_read = Array<ReadValueId>(std::move(ids));
  return r;
}

// A ReadResponse carrying one ByteString of `size` bytes.
inline ReadResponse read_response(std::uint32_t handle, std::size_t size = 0) {
  ReadResponse r;
  r.response_header.request_handle = handle;
  DataValue dv;
  Bytes payload(size);
  for (std::size_t i = 0; i < size; ++i) {
    payload[i] = static_cast<std::uint8_t>(i * 7U);
  }
  dv.value = Variant(ByteString(std::move(payload)));
  r.results = Array<DataValue>(std::vector<DataValue>{dv});
  return r;
}

inline Bytes body_of(const Message& m) {
  auto b = encode_message(m);
  EXPECT_TRUE(b.ok());
  return b.ok() ? *b : Bytes{};
}

// One symmetric chunk as a SecurityPolicy None peer would send it (OPC 10000-6 §6.7.2).
inline Bytes raw_chunk(std::string_view type, char chunk, std::uint32_t channel_id, std::uint32_t token_id,
                       std::uint32_t sequence_number, std::uint32_t request_id, ByteSpan body) {
  ByteWriter w;
  for (const char c : type) {
    w.u8(static_cast<std::uint8_t>(c));
  }
  w.u8(static_cast<std::uint8_t>(chunk));
  w.u32(0);
  w.u32(channel_id);
  w.u32(token_id);
  w.u32(sequence_number);
  w.u32(request_id);
  w.bytes(body);
  (void)w.patch<std::uint32_t>(4, static_cast<std::uint32_t>(w.size()));
  return w.take();
}

// An OPN chunk with a SecurityPolicy None style asymmetric header.
inline Bytes raw_open(std::uint32_t channel_id, std::string_view policy_uri, std::uint32_t sequence_number,
                      std::uint32_t request_id, const OpenSecureChannelRequest& request) {
  ByteWriter w;
  w.bytes(Bytes{'O', 'P', 'N', 'F'});
  w.u32(0);
  w.u32(channel_id);
  Encoder e(w);
  encode_binary(e, String(policy_uri));
  encode_binary(e, ByteString{});
  encode_binary(e, ByteString{});
  w.u32(sequence_number);
  w.u32(request_id);
  EXPECT_TRUE(encode_message(request, w).ok());
  (void)w.patch<std::uint32_t>(4, static_cast<std::uint32_t>(w.size()));
  return w.take();
}

inline OpenSecureChannelRequest open_request(SecurityTokenRequestType type, std::uint32_t lifetime = 60'000) {
  OpenSecureChannelRequest r;
  r.request_type = type;
  r.security_mode = MessageSecurityMode::None;
  r.client_nonce = ByteString(Bytes{});
  r.requested_lifetime = lifetime;
  return r;
}

inline std::size_t count(const std::vector<ChannelEvent>& events, ChannelEvent::Kind kind) {
  return static_cast<std::size_t>(
      std::count_if(events.begin(), events.end(), [kind](const ChannelEvent& e) { return e.kind == kind; }));
}

inline const ChannelEvent* last(const std::vector<ChannelEvent>& events, ChannelEvent::Kind kind) {
  for (auto it = events.rbegin(); it != events.rend(); ++it) {
    if (it->kind == kind) {
      return &*it;
    }
  }
  return nullptr;
}

// The chunks of a byte stream: (header, whole chunk).
inline std::vector<std::pair<MessageHeader, Bytes>> split_chunks(ByteSpan stream) {
  std::vector<std::pair<MessageHeader, Bytes>> out;
  while (stream.size() >= 8) {
    auto h = decode_header(stream);
    if (!h.ok() || h->size > stream.size()) {
      ADD_FAILURE() << "broken stream";
      break;
    }
    out.emplace_back(*h, Bytes(stream.begin(), stream.begin() + h->size));
    stream = stream.subspan(h->size);
  }
  return out;
}

// The token id of a symmetric chunk.
inline std::uint32_t token_of(const Bytes& chunk) {
  return load_le<std::uint32_t>(chunk.data() + 12);
}

struct Harness {
  explicit Harness(SecureChannelConfig c = client_config(), SecureChannelConfig s = server_config())
      : client(std::move(c), clock), server(std::move(s), clock) {}

  // Moves bytes both ways until both sides are quiet; remembers what the server sent.
  void pump() {
    for (int round = 0; round < 1000; ++round) {
      const Bytes c = client.take_output();
      const Bytes s = server.take_output();
      collect();
      if (c.empty() && s.empty()) {
        break;
      }
      server_sent.insert(server_sent.end(), s.begin(), s.end());
      server.receive(c);
      client.receive(s);
    }
    collect();
  }

  void open() {
    client.start();
    pump();
    ASSERT_TRUE(client.is_open()) << to_string(client.state());
    ASSERT_TRUE(server.is_open()) << to_string(server.state());
    server_sent.clear();
  }

  void collect() {
    for (auto& e : client.take_events()) {
      client_events.push_back(std::move(e));
    }
    for (auto& e : server.take_events()) {
      server_events.push_back(std::move(e));
    }
  }

  // Feeds raw bytes to the server and returns the ERR it answered with (fails if none).
  ErrorMessage server_rejects(ByteSpan bytes) {
    server.receive(bytes);
    collect();
    const Bytes out = server.take_output();
    auto header = decode_header(out);
    EXPECT_TRUE(header.ok());
    if (!header.ok()) {
      return {};
    }
    EXPECT_EQ(header->type, MessageType::Error);
    auto err = decode_error_body(ByteSpan(out).subspan(8, header->size - 8));
    EXPECT_TRUE(err.ok());
    EXPECT_TRUE(server.is_closed());
    const ChannelEvent* closed = last(server_events, ChannelEvent::Kind::Closed);
    EXPECT_NE(closed, nullptr);
    if (closed != nullptr && err.ok()) {
      EXPECT_EQ(closed->status, err->error);
    }
    return err.ok() ? *err : ErrorMessage{};
  }

  ManualClock clock;
  SecureChannel client;
  SecureChannel server;
  std::vector<ChannelEvent> client_events;
  std::vector<ChannelEvent> server_events;
  Bytes server_sent;
};

}  // namespace sf::opcua::test
