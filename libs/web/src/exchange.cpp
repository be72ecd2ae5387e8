#include "exchange.hpp"

#include <array>
#include <utility>

#include "static_files.hpp"
#include "target.hpp"

namespace sf::web {
namespace {

// Sent with every response: the dashboard loads only its own scripts and is never framed.
constexpr std::array<std::pair<std::string_view, std::string_view>, 4> kSecurityHeaders{{
    {"Content-Security-Policy", "default-src 'self'"},
    {"X-Content-Type-Options", "nosniff"},
    {"Referrer-Policy", "no-referrer"},
    {"X-Frame-Options", "DENY"},
}};

}  // namespace

Result<Request> to_request(BeastRequest& message) {
  auto target = parse_target(std::string_view(message.target().data(), message.target().size()));
  if (!target) {
    return target.error();
  }
  Request request;
  request.method = std::string(message.method_string());
  request.target = std::string(message.target());
  request.path = std::move(target->path);
  request.query_params = std::move(target->query);
  for (const auto& field : message) {
    request.headers.add(std::string(field.name_string()), std::string(field.value()));
  }
  request.body = std::move(message.body());
  return request;
}

namespace {

Response static_response(const Site& site, const Request& request) {
  const bool readable = request.method == "GET" || request.method == "HEAD";
  auto file = read_static_file(site.config.static_root, request.path);
  if (!file) {
    if (file.error().code == Errc::invalid_argument) {
      return error_response(400, file.error().message);
    }
    return error_response(404, "no route or file for " + request.path);
  }
  if (!readable) {
    auto response = error_response(405, "method " + request.method + " not allowed on " + request.path);
    response.headers.set("Allow", "GET, HEAD");
    return response;
  }
  Response response;
  response.content_type = std::move(file->content_type);
  response.body = std::move(file->body);
  return response;
}

Response respond(const Site& site, Request& request) {
  if (!site.config.live_path.empty() && request.path == site.config.live_path) {
    // RFC 9110 §15.5.22: the live endpoint speaks only WebSocket (RFC 6455 §4.2.1).
    auto response = error_response(426, request.path + " is a WebSocket endpoint");
    response.headers.set("Upgrade", "websocket");
    return response;
  }
  if (auto routed = site.router.dispatch(request)) {
    return std::move(*routed);
  }
  if (!site.config.static_root.empty()) {
    return static_response(site, request);
  }
  return error_response(404, "no route for " + request.path);
}

}  // namespace

void configure_parser(RequestParser& parser, const ServerConfig& config) {
  parser.header_limit(static_cast<std::uint32_t>(config.header_limit));
  parser.body_limit(config.body_limit);
}

Response parse_error_response(const beast::error_code& error) {
  if (error == http::error::body_limit) {
    return error_response(413, "request body larger than the server accepts");
  }
  if (error == http::error::header_limit) {
    return error_response(431, "request header section larger than the server accepts");
  }
  return error_response(400, "malformed request: " + error.message());
}

BeastResponse to_beast(Response response, unsigned version, bool keep_alive, bool head) {
  if (response.status < 100 || response.status > 599) {  // RFC 9110 §15: three digits, 1xx-5xx
    response = error_response(500, "handler returned an invalid status code");
  }
  BeastResponse out{static_cast<http::status>(response.status), version};
  out.reason(std::string(reason_phrase(response.status)));
  for (const auto& [name, value] : response.headers.all()) {
    out.set(name, value);
  }
  for (const auto& [name, value] : kSecurityHeaders) {
    out.set(beast::string_view(name.data(), name.size()), beast::string_view(value.data(), value.size()));
  }
  out.set(http::field::content_type, response.content_type);
  out.keep_alive(keep_alive);
  const auto length = response.body.size();
  if (!head) {
    out.body() = std::move(response.body);
  }
  out.content_length(length);
  return out;
}

BeastResponse answer(const Site& site, BeastRequest&& message) {
  const bool head = message.method() == http::verb::head;
  auto request = to_request(message);
  if (!request) {
    return to_beast(error_response(400, request.error().message), message.version(), false, head);
  }
  return to_beast(respond(site, *request), message.version(), message.keep_alive(), head);
}

BeastResponse answer_bytes(const Site& site, std::string_view bytes) {
  RequestParser parser;
  configure_parser(parser, site.config);
  beast::error_code error;
  std::size_t used = 0;
  while (!error && used < bytes.size() && !parser.is_done()) {
    const auto n = parser.put(boost::asio::buffer(bytes.data() + used, bytes.size() - used), error);
    used += n;
    if (error == http::error::need_more || (n == 0 && !error)) {
      error = {};
      break;
    }
  }
  if (!error && !parser.is_done()) {
    parser.put_eof(error);
  }
  if (error) {
    return to_beast(parse_error_response(error), 11, false, false);
  }
  return answer(site, parser.release());
}

}  // namespace sf::web
