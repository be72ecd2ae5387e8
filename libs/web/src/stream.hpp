// The byte stream of one connection: plain TCP, or TLS over it when the server has a certificate.
// HttpSession and LiveSession are written once against it (Beast's HTTP reads and writes and its
// WebSocket stream take any AsyncStream); only the start (the TLS handshake) and the WebSocket
// tear-down (TLS close_notify first, RFC 8446 §6.1) differ.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket/teardown.hpp>
#include <utility>
#include <variant>

namespace sf::web {

class Stream {
 public:
  using Plain = boost::beast::tcp_stream;
  using Tls = boost::beast::ssl_stream<boost::beast::tcp_stream>;
  using executor_type = Plain::executor_type;

  explicit Stream(Plain&& plain) : stream_(std::in_place_type<Plain>, std::move(plain)) {}
  Stream(Plain&& tcp, boost::asio::ssl::context& context)
      : stream_(std::in_place_type<Tls>, std::move(tcp), context) {}

  executor_type get_executor() { return next_layer().get_executor(); }

  // The TCP stream (its timeout, its socket); beast::get_lowest_layer finds it through here.
  Plain& next_layer() {
    auto* tls = std::get_if<Tls>(&stream_);
    return tls != nullptr ? tls->next_layer() : std::get<Plain>(stream_);
  }
  // The TLS layer, or null on a plain connection.
  Tls* tls() { return std::get_if<Tls>(&stream_); }

  // AsyncReadStream and AsyncWriteStream: the handler goes to whichever layer is on top.
  template <typename Buffers, typename Handler>
  void async_read_some(const Buffers& buffers, Handler&& handler) {
    std::visit([&](auto& s) { s.async_read_some(buffers, std::forward<Handler>(handler)); }, stream_);
  }
  template <typename Buffers, typename Handler>
  void async_write_some(const Buffers& buffers, Handler&& handler) {
    std::visit([&](auto& s) { s.async_write_some(buffers, std::forward<Handler>(handler)); }, stream_);
  }

  // The WebSocket closing handshake's last step (RFC 6455 §7.1.1), by Beast for each layer.
  template <typename Handler>
  friend void async_teardown(boost::beast::role_type role, Stream& stream, Handler&& handler) {
    std::visit(
        [&](auto& s) {
          using boost::beast::websocket::async_teardown;
          async_teardown(role, s, std::forward<Handler>(handler));
        },
        stream.stream_);
  }

 private:
  std::variant<Plain, Tls> stream_;
};

}  // namespace sf::web
