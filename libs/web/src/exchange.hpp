// One HTTP exchange on Boost.Beast: the request parser with the server's limits, the request
// as sf::web::Request, the answer (router, then static files), the response with the security
// headers. The connection code and the fuzz target share these functions, so the fuzzer runs
// exactly the path a request from the network takes.
#pragma once

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <string_view>

#include "sf/web/message.hpp"
#include "sf/web/server.hpp"

namespace sf::web {

namespace beast = boost::beast;
namespace http = boost::beast::http;
using BeastRequest = http::request<http::string_body>;
using BeastResponse = http::response<http::string_body>;
using RequestParser = http::request_parser<http::string_body>;

// What a request is answered from.
struct Site {
  const ServerConfig& config;
  const Router& router;
};

// A parser for one request, holding the configured header and body limits (RFC 9112 §2.3).
void configure_parser(RequestParser& parser, const ServerConfig& config);

// A Beast request as a Request (the body moved out); errors for a target we do not accept.
Result<Request> to_request(BeastRequest& message);

// The response to a request that could not be parsed: 413, 431 or 400.
Response parse_error_response(const beast::error_code& error);

// The answer to a parsed request, with security headers; the caller only writes it.
BeastResponse answer(const Site& site, BeastRequest&& request);

// A Response as Beast's message: status line, Content-Type, security headers, the body
// (omitted for HEAD, RFC 9110 §9.3.2, with the Content-Length of GET).
BeastResponse to_beast(Response response, unsigned version, bool keep_alive, bool head);

// Raw bytes through the same parser and answer(): what the fuzz target drives.
BeastResponse answer_bytes(const Site& site, std::string_view bytes);

}  // namespace sf::web
