// The live endpoint's input on arbitrary bytes: after an opening handshake, the bytes are a
// client's frames (RFC 6455 §5) through Beast's server-side frame decoder with the server's
// message limit, and each text message through the live protocol's parser. Every frame
// sequence ends in messages or a clean failure; every refused message has a reason.
#include <boost/beast/_experimental/test/stream.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "live_protocol.hpp"
#include "sf/web/server.hpp"

namespace {

namespace beast = boost::beast;

constexpr std::string_view kHandshake =
    "GET /api/live HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
    "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";

void check_message(std::string_view text) {
  auto request = sf::web::parse_live_request(text);
  if (request) {
    for (const auto& topic : request->topics) {
      if (topic.empty()) {
        __builtin_trap();
      }
    }
  } else if (request.error().message.empty()) {
    __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const sf::web::ServerConfig config;
  boost::asio::io_context context;
  beast::test::stream server(context);
  beast::test::stream client(context);
  server.connect(client);
  server.append(beast::string_view(kHandshake.data(), kHandshake.size()));
  server.append(beast::string_view(reinterpret_cast<const char*>(data), size));  // NOLINT
  client.close();  // the server reads end of stream after the bytes

  beast::websocket::stream<beast::test::stream> ws(std::move(server));
  ws.read_message_max(config.live_message_limit);
  beast::error_code error;
  ws.accept(error);
  if (error) {
    __builtin_trap();  // the handshake is fixed and valid
  }
  while (!error) {
    beast::flat_buffer buffer;
    ws.read(buffer, error);
    if (!error && ws.got_text()) {
      check_message(beast::buffers_to_string(buffer.data()));
    }
  }
  return 0;
}
