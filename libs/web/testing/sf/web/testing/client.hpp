// Clients for the tests of web servers (libs/web, libs/dashboard): Boost.Beast's HTTP and WebSocket clients
// over loopback (HTTP also over TLS), and a raw socket for bytes no well-behaved client sends. The reads
// block (Asio's synchronous reads ignore SO_RCVTIMEO): an HTTP read the server never answers ends with the
// server's idle timeout (kTestIdleTimeout), a live read with the test's timeout.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

namespace sf::web::testing {

namespace http = boost::beast::http;
using HttpResponse = http::response<http::string_body>;

// Polls until the server reaches a state the test waits for (a connection accepted or gone);
// the test's own timeout ends a wait that never ends.
template <typename Predicate>
void wait_until(Predicate done) {
  while (!done()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

using HeaderList = std::vector<std::pair<std::string, std::string>>;

// One request on a fresh connection, with these header fields besides Host and Content-Type.
HttpResponse http_request(std::uint16_t port, http::verb method, std::string_view target,
                          std::string body = {}, std::string_view content_type = "application/json",
                          const HeaderList& headers = {});
// The same over TLS, the server's certificate verified against `ca` (PEM) and 127.0.0.1.
HttpResponse https_request(const std::filesystem::path& ca, std::uint16_t port, http::verb method,
                           std::string_view target, std::string body = {},
                           std::string_view content_type = "application/json",
                           const HeaderList& headers = {});

// Writes bytes on a fresh connection and returns everything read until the server closes or
// a read times out.
std::string raw_exchange(std::uint16_t port, std::string_view bytes);

// The status code of a raw HTTP response ("HTTP/1.1 400 ..." → 400), 0 if none.
int raw_status(std::string_view response);

// The idle timeout of the servers under test: a read they never answer fails after it.
constexpr int kTestIdleTimeout = 5;

// A connected socket; receive_buffer > 0 sets a small SO_RCVBUF.
boost::asio::ip::tcp::socket connect(boost::asio::io_context& context, std::uint16_t port,
                                     int receive_buffer = 0);

// Writes bytes on a socket and reads the header of the response that follows (an interim or
// 101 response has no body); what follows stays in `buffer`.
int write_and_read_status(boost::asio::ip::tcp::socket& socket, boost::beast::flat_buffer& buffer,
                          std::string_view bytes);

// A raw connection, for what no well-behaved client sends: its socket and read buffer.
struct RawConnection {
  explicit RawConnection(std::uint16_t port) : socket(connect(context, port)) {}
  // Writes bytes and reads the header of the response (write_and_read_status).
  int status(std::string_view bytes) { return write_and_read_status(socket, buffer, bytes); }
  boost::asio::io_context context;
  boost::asio::ip::tcp::socket socket;
  boost::beast::flat_buffer buffer;
};

class LiveClient {
 public:
  // receive_buffer > 0: a small SO_RCVBUF, for a client that reads slowly.
  // cookie: a Cookie header field for the handshake.
  explicit LiveClient(std::uint16_t port, int receive_buffer = 0, const std::string& cookie = {});
  void send(std::string_view text);
  void send_binary(std::string_view bytes);
  // The next message as JSON; throws on a closed connection.
  nlohmann::json receive();
  // Reads until the connection closes; the close code received (0 if none).
  int close_code();

 private:
  boost::asio::io_context context_;
  boost::beast::websocket::stream<boost::asio::ip::tcp::socket> ws_;
};

}  // namespace sf::web::testing
