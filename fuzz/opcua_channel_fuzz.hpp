// Shared by the secure channel fuzz targets (opcua_transport_fuzz, opcua_secure_channel_fuzz): a
// server-role sf::opcua::SecureChannel with small limits, a handshake with an in-memory client, and the
// draining of its events that answers every delivered request and checks the event stream.
#pragma once

#include <cstdint>

#include "sf/core/clock.hpp"
#include "sf/opcua/transport/secure_channel.hpp"

namespace opcua_fuzz {

inline void check(bool ok) {
  if (!ok) {
    __builtin_trap();
  }
}

inline sf::opcua::SecureChannelConfig server_config() {
  sf::opcua::SecureChannelConfig c;
  c.role = sf::opcua::ChannelRole::Server;
  c.channel_id = 77;
  c.limits.receive_buffer_size = 8192;
  c.limits.max_message_size = 64 * 1024;
  c.limits.max_chunk_count = 16;
  c.decode_limits.max_string_length = 4096;
  c.decode_limits.max_array_length = 256;
  c.decode_limits.max_depth = 16;
  return c;
}

// Opens `server` with a client of `client_config` (HEL/ACK, OPN); returns the client's next
// sequence number.
inline std::uint32_t open(sf::opcua::SecureChannel& server, sf::opcua::SecureChannelConfig client_config,
                          const sf::Clock& clock) {
  client_config.role = sf::opcua::ChannelRole::Client;
  client_config.endpoint_url = "opc.tcp://fuzz";
  sf::opcua::SecureChannel client(client_config, clock);
  client.start();
  for (int i = 0; i < 4; ++i) {
    server.receive(client.take_output());
    client.receive(server.take_output());
  }
  check(server.is_open() && client.is_open());
  (void)server.take_events();
  return 2;  // the OPN used sequence number 1
}

// Answers what was delivered (so sending runs too) and checks the event stream's shape.
inline void drain(sf::opcua::SecureChannel& server, bool& closed) {
  for (auto& event : server.take_events()) {
    check(!closed);  // Closed is the last event
    if (event.kind == sf::opcua::ChannelEvent::Kind::ServiceMessage ||
        event.kind == sf::opcua::ChannelEvent::Kind::Undecodable) {
      sf::opcua::ServiceFault fault;
      fault.response_header.request_handle = event.request_handle;
      fault.response_header.service_result = event.status;
      (void)server.send_response(event.request_id, fault);
    } else if (event.kind == sf::opcua::ChannelEvent::Kind::Closed) {
      closed = true;
      check(server.is_closed());
    }
  }
  (void)server.take_output();
}

}  // namespace opcua_fuzz
