// The web server's request path on arbitrary bytes: Beast's parser with the server's limits,
// the request-target's decoding, the router and the static files (sf::web answer_bytes, the
// functions a connection calls). Every input gets a response with a valid status and the
// security headers, and no response is ever the file outside the static root.
#include <stdlib.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "exchange.hpp"
#include "sf/core/log.hpp"

namespace {

constexpr std::string_view kSecret = "sf-web-fuzz-secret-outside-the-root";

std::filesystem::path make_site() {
  std::string pattern = (std::filesystem::temp_directory_path() / "sf-web-fuzz-XXXXXX").string();
  const std::filesystem::path dir = ::mkdtemp(pattern.data()) != nullptr ? pattern : std::string{};
  std::ofstream(dir / "secret.txt") << kSecret;
  std::filesystem::create_directories(dir / "site/js");
  std::ofstream(dir / "site/index.html") << "<!doctype html>";
  std::ofstream(dir / "site/js/app.js") << "export {}";
  static const std::filesystem::path kept = dir;
  ::atexit([] {
    std::error_code ignored;
    std::filesystem::remove_all(kept, ignored);
  });
  return dir / "site";
}

sf::web::Router make_router() {
  using sf::web::Request;
  using sf::web::Response;
  sf::web::Router router;
  (void)router.add("GET", "/api/orders/{id}", [](const Request& r) {
    return sf::web::json_response({{"id", r.path_params.at("id")}, {"query", r.query_params}});
  });
  (void)router.add("POST", "/api/orders", [](const Request& r) {
    auto body = sf::web::json_body(r);
    return body ? sf::web::json_response(*body, 201) : sf::web::error_response(400, body.error().message);
  });
  (void)router.add("GET", "/api/fail/{what}",
                   [](const Request&) -> Response { throw std::runtime_error("x"); });
  (void)router.add("GET", "/api/status/{code}", [](const Request& r) {
    Response response;
    response.status = std::atoi(r.path_params.at("code").c_str());  // also codes out of range
    return response;
  });
  return router;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = sf::log::set_level("off").ok();
  static const sf::web::ServerConfig config = [] {
    sf::web::ServerConfig c;
    c.static_root = make_site();
    c.body_limit = 4096;
    c.header_limit = 2048;
    return c;
  }();
  static const sf::web::Router router = make_router();
  (void)quiet;

  const std::string_view bytes(reinterpret_cast<const char*>(data), size);  // NOLINT
  const auto response = sf::web::answer_bytes(sf::web::Site{config, router}, bytes);
  const unsigned status = response.result_int();
  if (status < 100 || status > 599 || response["X-Content-Type-Options"] != "nosniff" ||
      response["Content-Security-Policy"] != "default-src 'self'" ||
      response.body() == kSecret) {  // errors may quote the request, never serve the file
    __builtin_trap();
  }
  return 0;
}
