#include "http_session.hpp"

#include <boost/asio/dispatch.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <utility>

#include "live_session.hpp"
#include "sf/core/log.hpp"
#include "target.hpp"

namespace sf::web {
namespace net = boost::asio;

namespace {

bool is_live_upgrade(const ServerConfig& config, const BeastRequest& request) {
  if (config.live_path.empty() || !beast::websocket::is_upgrade(request)) {
    return false;
  }
  auto target = parse_target(std::string_view(request.target().data(), request.target().size()));
  return target && target->path == config.live_path;
}

// How long and how much of a refused request is still read after the answer, so that closing
// with unread bytes does not reset the connection before the peer reads the answer
// (RFC 9112 §9.6, tear-down).
constexpr auto kLingerTime = std::chrono::seconds(2);
constexpr std::size_t kLingerBytes = 1024UL * 1024UL;

// RFC 6797 §6.1: browsers that reached us over TLS keep to HTTPS for a year.
constexpr const char* kStrictTransportSecurity = "max-age=31536000";

Stream open_stream(net::ip::tcp::socket&& socket, const ServerState& state) {
  if (state.tls) {
    return {beast::tcp_stream(std::move(socket)), *state.tls};
  }
  return Stream(beast::tcp_stream(std::move(socket)));
}

}  // namespace

HttpSession::HttpSession(net::ip::tcp::socket&& socket, std::shared_ptr<ServerState> state,
                         std::shared_ptr<ConnectionSlot> slot)
    : stream_(open_stream(std::move(socket), *state)), state_(std::move(state)), slot_(std::move(slot)) {}

void HttpSession::run() {
  // Start on the connection's strand: its handlers never run concurrently.
  net::dispatch(stream_.get_executor(), [self = shared_from_this()] {
    if (auto* tls = self->stream_.tls()) {
      self->handshake(*tls);
      return;
    }
    self->serve();
  });
}

void HttpSession::handshake(Stream::Tls& tls) {
  beast::get_lowest_layer(stream_).expires_after(
      std::chrono::seconds(state_->config.tls->handshake_timeout_seconds));
  tls.async_handshake(
      net::ssl::stream_base::server,
      [self = shared_from_this()](const beast::error_code& error) { self->on_handshake(error); });
}

void HttpSession::on_handshake(const beast::error_code& error) {
  if (!error) {
    serve();
    return;
  }
  // Garbage, plain HTTP, a protocol or cipher we do not offer, a peer that stalls: nothing can be
  // answered without a session; the alert that says why is OpenSSL's to send (RFC 8446 §6.2).
  ++state_->tls_failures;
  sf::log::get("web")->debug("tls handshake failed: {}", error.message());
  close();
}

void HttpSession::serve() {
  if (!slot_) {
    write(to_beast(error_response(503, "too many connections"), 11, false, false));
    return;
  }
  read_next();
}

void HttpSession::read_next() {
  parser_.emplace();
  configure_parser(*parser_, state_->config);
  beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(state_->config.idle_timeout_seconds));
  http::async_read_header(
      stream_, buffer_, *parser_,
      [self = shared_from_this()](const beast::error_code& error, std::size_t) { self->on_header(error); });
}

void HttpSession::on_header(const beast::error_code& error) {
  if (error || parser_->is_done()) {
    on_read(error);
    return;
  }
  // RFC 9110 §10.1.1: a client that expects 100-continue waits for it before the body. The
  // header passed the limits (a declared body over body_limit has already failed).
  const auto expect = parser_->get()[http::field::expect];
  if (beast::iequals(expect, "100-continue")) {
    auto interim = std::make_shared<http::response<http::empty_body>>(http::status::continue_, 11);
    http::async_write(
        stream_, *interim,
        [self = shared_from_this(), interim](const beast::error_code& write_error, std::size_t) {
          if (write_error) {
            self->close();
            return;
          }
          self->read_body();
        });
    return;
  }
  read_body();
}

void HttpSession::read_body() {
  http::async_read(
      stream_, buffer_, *parser_,
      [self = shared_from_this()](const beast::error_code& error, std::size_t) { self->on_read(error); });
}

void HttpSession::on_read(const beast::error_code& error) {
  if (error == http::error::end_of_stream || error == beast::error::timeout ||
      error == net::error::operation_aborted || error == net::error::connection_reset ||
      error == net::error::eof) {
    close();
    return;
  }
  if (error) {
    // Nothing more is read from a connection whose framing is lost (RFC 9112 §9.6).
    write(to_beast(parse_error_response(error), 11, false, false));
    return;
  }
  if (is_live_upgrade(state_->config, parser_->get())) {
    upgrade();
    return;
  }
  write(answer(Site{state_->config, state_->router}, parser_->release()));
}

void HttpSession::upgrade() {
  BeastRequest request = parser_->release();
  TopicFilter filter;
  if (state_->config.live_access) {
    BeastRequest copy = request;
    auto decoded = to_request(copy);
    if (!decoded) {
      write(to_beast(error_response(400, decoded.error().message), request.version(), false, false));
      return;
    }
    auto access = state_->config.live_access(*decoded);
    if (auto* refused = std::get_if<Response>(&access)) {
      write(to_beast(std::move(*refused), request.version(), false, false));
      return;
    }
    filter = std::get<TopicFilter>(std::move(access));
  }
  auto live = std::make_shared<LiveSession>(std::move(stream_), state_->hub, state_->config, std::move(slot_),
                                            std::move(filter));
  live->run(request);
}

void HttpSession::write(BeastResponse response) {
  ++state_->requests;
  response_ = std::make_shared<BeastResponse>(std::move(response));
  if (state_->tls) {
    response_->set(http::field::strict_transport_security, kStrictTransportSecurity);
  }
  beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(state_->config.idle_timeout_seconds));
  http::async_write(stream_, *response_,
                    [self = shared_from_this()](const beast::error_code& error, std::size_t) {
                      if (error) {
                        self->close();
                        return;
                      }
                      if (!self->response_->keep_alive()) {
                        self->linger();
                        return;
                      }
                      self->read_next();
                    });
}

void HttpSession::linger() {
  auto& tcp = beast::get_lowest_layer(stream_);
  beast::error_code ignored;
  tcp.socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
  tcp.expires_after(kLingerTime);
  drained_ = 0;
  drain();
}

void HttpSession::drain() {
  buffer_.consume(buffer_.size());
  stream_.async_read_some(buffer_.prepare(16UL * 1024UL),
                          [self = shared_from_this()](const beast::error_code& error, std::size_t n) {
                            self->drained_ += n;
                            if (error || self->drained_ > kLingerBytes) {
                              self->close();
                              return;
                            }
                            self->drain();
                          });
}

void HttpSession::close() {
  auto& tcp = beast::get_lowest_layer(stream_);
  beast::error_code ignored;
  tcp.socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
  tcp.close();
}

}  // namespace sf::web
