// Fuzzes the server side of UA-TCP and the secure channel (OPC 10000-6 §6.7, §7.1) with
// arbitrary bytes: a server-role SecureChannel must reject or accept any input without
// reading out of bounds, growing without bound or misbehaving afterwards. The first byte picks
// where the input lands:
//   0: on a fresh connection (before HEL)
//   1: after a valid HEL
//   2: on an open channel (after HEL/ACK and OPN), as raw bytes
//   3: on an open channel, as MSG chunks whose headers, channel id, token id and sequence
//      numbers the harness fills in, so the fuzzer reaches chunk assembly and body decoding.
#include <cstddef>
#include <cstdint>

#include "opcua_channel_fuzz.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/encoding.hpp"
#include "sf/opcua/transport/secure_channel.hpp"

namespace {

using namespace sf::opcua;
using namespace opcua_fuzz;

void feed_chunks(SecureChannel& server, sf::ByteSpan input, std::uint32_t sequence, bool& closed) {
  sf::ByteReader r(input);
  while (r.remaining() >= 3 && !closed) {
    const std::uint8_t control = r.u8();
    const std::size_t length = r.u16();
    const sf::ByteSpan body = r.bytes(std::min(length, r.remaining()));
    const char chunk = "FCAF"[control & 3U];
    sf::ByteWriter w;
    w.bytes(sf::Bytes{'M', 'S', 'G', static_cast<std::uint8_t>(chunk)});
    w.u32(0);
    w.u32((control & 0x40U) != 0 ? 78 : 77);
    w.u32((control & 0x20U) != 0 ? 2 : 1);
    w.u32((control & 0x80U) != 0 ? sequence + 7 : sequence);
    w.u32((control >> 2U) & 7U);
    w.bytes(body);
    (void)w.patch<std::uint32_t>(4, static_cast<std::uint32_t>(w.size()));
    ++sequence;
    server.receive(w.data());
    drain(server, closed);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Every rejected input is logged; at fuzzing rates that is all the fuzzer would do.
  (void)sf::log::set_level("off");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  sf::ManualClock clock;
  SecureChannel server(server_config(), clock);
  const std::uint8_t mode = data[0] & 3U;
  const sf::ByteSpan input(data + 1, size - 1);
  bool closed = false;
  std::uint32_t sequence = 1;
  if (mode == 1) {
    server.receive(encode_hello(make_hello(TransportLimits{}, "opc.tcp://fuzz")));
    (void)server.take_output();
  } else if (mode >= 2) {
    sequence = open(server, SecureChannelConfig{}, clock);
  }
  if (mode == 3) {
    feed_chunks(server, input, sequence, closed);
  } else {
    // Two pieces, so partial headers and chunks are buffered across calls.
    const std::size_t split = input.empty() ? 0 : input[0] % (input.size() + 1);
    server.receive(input.first(split));
    drain(server, closed);
    server.receive(input.subspan(split));
    drain(server, closed);
  }
  clock.advance(std::chrono::hours{2});  // past every token lifetime
  server.on_timer();
  drain(server, closed);
  check(!server.is_open());
  return 0;
}
