// One HTTP/1.1 connection (RFC 9112), plain or over TLS: the TLS handshake first, then requests
// read one at a time with the configured limits, each answered before the next is read (no
// pipelining in parallel, RFC 9112 §9.3.2); an upgrade to the live endpoint hands the connection
// to a LiveSession.
#pragma once

#include <atomic>
#include <boost/asio/ssl/context.hpp>
#include <boost/beast/core.hpp>
#include <memory>
#include <optional>

#include "exchange.hpp"
#include "stream.hpp"

namespace sf::web {

class ConnectionSlot;
class LiveHub;

// What every connection shares with the server; outlives the server's io_context.
struct ServerState {
  ServerConfig config;
  Router router;
  std::shared_ptr<LiveHub> hub;
  std::shared_ptr<boost::asio::ssl::context> tls;  // set by start() when config.tls is
  std::atomic<std::size_t> connections{0};
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> refused{0};
  std::atomic<std::uint64_t> tls_failures{0};
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // slot empty: the connection is over the limit and is answered 503, then closed. TLS when the
  // state has a TLS context.
  HttpSession(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<ServerState> state,
              std::shared_ptr<ConnectionSlot> slot);
  void run();

 private:
  void handshake(Stream::Tls& tls);
  void on_handshake(const beast::error_code& error);
  void serve();
  void read_next();
  void on_header(const beast::error_code& error);
  void read_body();
  void on_read(const beast::error_code& error);
  void write(BeastResponse response);
  // The live endpoint's upgrade: ServerConfig::live_access decides, then the LiveSession takes
  // the connection.
  void upgrade();
  void linger();
  void drain();
  void close();

  Stream stream_;
  beast::flat_buffer buffer_;
  std::shared_ptr<ServerState> state_;
  std::shared_ptr<ConnectionSlot> slot_;
  std::optional<RequestParser> parser_;
  std::shared_ptr<BeastResponse> response_;
  std::size_t drained_ = 0;
};

}  // namespace sf::web
