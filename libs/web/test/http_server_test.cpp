// The server over real loopback connections: routing, every class of bad request, limits,
// static files and the security headers.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "sf/testing/temp_dir.hpp"
#include "sf/web/server.hpp"
#include "sf/web/testing/client.hpp"

namespace sf::web {
namespace {

using testing::http_request;
using testing::raw_exchange;
using testing::raw_status;
namespace http = boost::beast::http;

Router api_router() {
  Router router;
  EXPECT_TRUE(router.add("GET", "/api/orders/{id}", [](const Request& r) {
    return json_response({{"id", r.path_params.at("id")},
                          {"detail", r.query_params.contains("detail") ? r.query_params.at("detail") : ""}});
  }));
  EXPECT_TRUE(router.add("POST", "/api/orders", [](const Request& r) {
    auto body = json_body(r);
    if (!body) {
      return error_response(400, body.error().message);
    }
    return json_response(
        {{"placed", *body}, {"agent", std::string(r.headers.get("user-agent").value_or(""))}}, 201);
  }));
  EXPECT_TRUE(
      router.add("GET", "/api/boom", [](const Request&) -> Response { throw std::logic_error("bug"); }));
  return router;
}

class HttpServerTest : public ::testing::Test {
 protected:
  void start(ServerConfig config = {}) {
    config.idle_timeout_seconds = testing::kTestIdleTimeout;
    server_ = std::make_unique<HttpServer>(std::move(config), api_router());
    auto port = server_->start();
    ASSERT_TRUE(port) << port.error().describe();
    port_ = *port;
  }
  static nlohmann::json json(const testing::HttpResponse& response) {
    return nlohmann::json::parse(response.body());
  }
  static void expect_security_headers(const testing::HttpResponse& response) {
    EXPECT_EQ(response["Content-Security-Policy"], "default-src 'self'");
    EXPECT_EQ(response["X-Content-Type-Options"], "nosniff");
    EXPECT_EQ(response["Referrer-Policy"], "no-referrer");
    EXPECT_EQ(response["X-Frame-Options"], "DENY");
    EXPECT_EQ(response.count(http::field::strict_transport_security), 0U);  // only over TLS
  }
  // A JSON error with the given status: {"error": "...", "status": N}.
  static void expect_json_error(const testing::HttpResponse& response, int status) {
    EXPECT_EQ(response.result_int(), static_cast<unsigned>(status));
    EXPECT_EQ(response[http::field::content_type], "application/json");
    const auto body = json(response);
    EXPECT_EQ(body.at("status"), status);
    EXPECT_FALSE(body.at("error").get<std::string>().empty());
    expect_security_headers(response);
  }
  // A refusal with the header that says what would be accepted (Allow, Upgrade).
  void expect_refusal(http::verb verb, const std::string& target, int status, http::field field,
                      const char* value) const {
    const auto response = http_request(port_, verb, target);
    expect_json_error(response, status);
    EXPECT_EQ(response[field], value);
  }

  std::unique_ptr<HttpServer> server_;
  std::uint16_t port_ = 0;
};

TEST_F(HttpServerTest, RoutesWithPathAndQueryParameters) {
  start();
  auto response = http_request(port_, http::verb::get, "/api/orders/A-17?detail=route%20map");
  EXPECT_EQ(response.result_int(), 200U);
  EXPECT_EQ(json(response), (nlohmann::json{{"id", "A-17"}, {"detail", "route map"}}));
  expect_security_headers(response);

  auto placed = http_request(port_, http::verb::post, "/api/orders", R"({"box":"small"})");
  EXPECT_EQ(placed.result_int(), 201U);
  EXPECT_EQ(json(placed).at("placed").at("box"), "small");
}

TEST_F(HttpServerTest, UnknownRouteIs404) {
  start();
  expect_json_error(http_request(port_, http::verb::get, "/api/nothing"), 404);
}

TEST_F(HttpServerTest, WrongMethodIs405WithAllow) {
  start();
  expect_refusal(http::verb::delete_, "/api/orders", 405, http::field::allow, "POST");
}

TEST_F(HttpServerTest, MalformedJsonBodyIs400FromTheHandler) {
  start();
  expect_json_error(http_request(port_, http::verb::post, "/api/orders", "{\"box\":"), 400);
}

TEST_F(HttpServerTest, MalformedRequestsAre400AndTheServerSurvives) {
  start();
  for (const char* bytes :
       {"GARBAGE\r\n\r\n", "GET /api/orders/1 HTTP/9.9\r\n\r\n",
        "GET /api/orders/1 HTTP/1.1\r\nHost: x\r\nContent-Length: abc\r\n\r\n",
        "GET /api/orders/1 HTTP/1.1\r\nBad Header\r\n\r\n",
        "GET http://elsewhere/ HTTP/1.1\r\nHost: x\r\n\r\n", "GET /a%zz HTTP/1.1\r\nHost: x\r\n\r\n"}) {
    const auto answer = raw_exchange(port_, bytes);
    EXPECT_EQ(raw_status(answer), 400) << bytes;
    EXPECT_NE(answer.find("\"error\""), std::string::npos) << bytes;
    EXPECT_NE(answer.find("X-Frame-Options: DENY"), std::string::npos) << bytes;
  }
  EXPECT_EQ(http_request(port_, http::verb::get, "/api/orders/1").result_int(), 200U);
}

TEST_F(HttpServerTest, BodyOverTheLimitIs413) {
  ServerConfig config;
  config.body_limit = 1024;
  start(config);
  expect_json_error(http_request(port_, http::verb::post, "/api/orders", std::string(64UL * 1024UL, 'x')),
                    413);
  // A chunked body is counted as it arrives (RFC 9112 §7.1).
  const auto answer =
      raw_exchange(port_,
                   "POST /api/orders HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
                   "800\r\n" +
                       std::string(0x800, 'x') + "\r\n0\r\n\r\n");
  EXPECT_EQ(raw_status(answer), 413);
  EXPECT_EQ(http_request(port_, http::verb::post, "/api/orders", "{}").result_int(), 201U);
}

// RFC 9110 §10.1.1: the client sends the body only after the interim 100 (Continue).
TEST_F(HttpServerTest, AnswersExpect100ContinueBeforeTheBody) {
  start();
  testing::RawConnection raw(port_);
  // Throws at the idle timeout if the server waits for the body.
  EXPECT_EQ(raw.status("POST /api/orders HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                       "Content-Length: 2\r\nExpect: 100-continue\r\n\r\n"),
            100);
  boost::asio::write(raw.socket, boost::asio::buffer(std::string_view("{}")));
  http::response<http::string_body> response;
  http::read(raw.socket, raw.buffer, response);
  EXPECT_EQ(response.result_int(), 201U);
}

TEST_F(HttpServerTest, HeaderSectionOverTheLimitIs431) {
  ServerConfig config;
  config.header_limit = 1024;
  start(config);
  const auto answer = raw_exchange(
      port_, "GET /api/orders/1 HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(4096, 'y') + "\r\n\r\n");
  EXPECT_EQ(raw_status(answer), 431);
}

TEST_F(HttpServerTest, ThrowingHandlerIs500AndTheServerSurvives) {
  start();
  auto response = http_request(port_, http::verb::get, "/api/boom");
  expect_json_error(response, 500);
  EXPECT_EQ(response.body().find("bug"), std::string::npos);
  EXPECT_EQ(http_request(port_, http::verb::get, "/api/orders/2").result_int(), 200U);
}

TEST_F(HttpServerTest, ConnectionsOverTheLimitAre503) {
  ServerConfig config;
  config.max_connections = 2;
  start(config);
  boost::asio::io_context context;
  auto first = testing::connect(context, port_);
  auto second = testing::connect(context, port_);
  testing::wait_until([&] { return server_->stats().connections == 2; });
  expect_json_error(http_request(port_, http::verb::get, "/api/orders/3"), 503);
  EXPECT_EQ(server_->stats().refused_connections, 1U);
  first.close();
  testing::wait_until([&] { return server_->stats().connections < 2; });
  EXPECT_EQ(http_request(port_, http::verb::get, "/api/orders/3").result_int(), 200U);
}

TEST_F(HttpServerTest, LivePathWithoutUpgradeIs426) {
  start();
  expect_refusal(http::verb::get, "/api/live", 426, http::field::upgrade, "websocket");
}

TEST_F(HttpServerTest, KeepsTheConnectionForTheNextRequest) {
  start();
  const auto answer = raw_exchange(port_,
                                   "GET /api/orders/1 HTTP/1.1\r\nHost: x\r\n\r\n"
                                   "GET /api/orders/2 HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(answer.find(R"("id":"1")"), std::string::npos);
  EXPECT_NE(answer.find(R"("id":"2")"), std::string::npos);
  EXPECT_EQ(server_->stats().requests, 2U);
}

TEST_F(HttpServerTest, ServesConcurrentClientsOnSeveralThreads) {
  ServerConfig config;
  config.threads = 2;
  start(config);
  constexpr int kClients = 6;
  constexpr int kRequests = 20;
  std::vector<int> answered(kClients, 0);
  std::vector<std::thread> clients;
  clients.reserve(kClients);
  for (int c = 0; c < kClients; ++c) {
    clients.emplace_back([&, c] {
      for (int r = 0; r < kRequests; ++r) {
        const auto id = std::to_string(c) + "-" + std::to_string(r);
        auto response = http_request(port_, http::verb::get, "/api/orders/" + id);
        answered[static_cast<std::size_t>(c)] +=
            response.result_int() == 200U && json(response).at("id") == id;
      }
    });
  }
  for (auto& client : clients) {
    client.join();
  }
  EXPECT_EQ(answered, std::vector<int>(kClients, kRequests));
  EXPECT_EQ(server_->stats().requests, static_cast<std::uint64_t>(kClients * kRequests));
}

TEST_F(HttpServerTest, StopClosesOpenConnectionsAndThePort) {
  start();
  boost::asio::io_context context;
  auto idle = testing::connect(context, port_);
  testing::wait_until([&] { return server_->stats().connections == 1; });
  server_->stop();
  char byte = 0;
  boost::beast::error_code error;
  idle.read_some(boost::asio::buffer(&byte, 1), error);
  EXPECT_EQ(error, boost::asio::error::eof);
  EXPECT_THROW(testing::connect(context, port_), boost::system::system_error);
  server_->stop();  // idempotent
}

TEST_F(HttpServerTest, RefusesABadListenAddress) {
  ServerConfig config;
  config.host = "not-an-address";
  HttpServer server(config, Router{});
  auto port = server.start();
  ASSERT_FALSE(port);
  EXPECT_EQ(port.error().code, Errc::invalid_argument);
}

class StaticFilesServerTest : public HttpServerTest {
 protected:
  void SetUp() override {
    write(dir_.path() / "secret.txt", "secret");
    write(dir_.path() / "site/index.html", "<!doctype html>");
    write(dir_.path() / "site/js/app.js", "export const x = 1;");
    write(dir_.path() / "site/css/site.css", "body{}");
    ServerConfig config;
    config.static_root = dir_.path() / "site";
    start(config);
  }
  static void write(const std::filesystem::path& path, std::string_view text) {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
  }
  sf::testing::TempDir dir_;
};

TEST_F(StaticFilesServerTest, ServesFilesWithTheirContentTypes) {
  for (const auto& [target, type, body] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"/", "text/html; charset=utf-8", "<!doctype html>"},
           {"/index.html", "text/html; charset=utf-8", "<!doctype html>"},
           {"/js/app.js", "text/javascript; charset=utf-8", "export const x = 1;"},
           {"/css/site.css?v=2", "text/css; charset=utf-8", "body{}"}}) {
    auto response = http_request(port_, http::verb::get, target);
    EXPECT_EQ(response.result_int(), 200U) << target;
    EXPECT_EQ(response[http::field::content_type], type) << target;
    EXPECT_EQ(response.body(), body) << target;
    expect_security_headers(response);
  }
  auto head = http_request(port_, http::verb::head, "/js/app.js");
  EXPECT_EQ(head.result_int(), 200U);
  EXPECT_EQ(head[http::field::content_length], "19");
  expect_json_error(http_request(port_, http::verb::get, "/js/none.js"), 404);
  auto post = http_request(port_, http::verb::post, "/index.html", "{}");
  expect_json_error(post, 405);
  EXPECT_EQ(post[http::field::allow], "GET, HEAD");
  // Routes come first: the API is reached with a static root too.
  EXPECT_EQ(http_request(port_, http::verb::get, "/api/orders/5").result_int(), 200U);
}

TEST_F(StaticFilesServerTest, TraversalAttemptsAreRefused) {
  for (const std::string& target : std::vector<std::string>{
           "/../secret.txt", "/js/../../secret.txt", "/%2e%2e/secret.txt", "/%2E%2E/secret.txt",
           "/js/%2e%2e/%2e%2e/secret.txt", "/..%2fsecret.txt", "/%252e%252e/secret.txt",
           "//" + (dir_.path() / "secret.txt").string(), "/.%2e/secret.txt", "/js/..\\..\\secret.txt"}) {
    const auto answer = raw_exchange(port_, "GET " + target + " HTTP/1.1\r\nHost: x\r\n\r\n");
    const int status = raw_status(answer);
    EXPECT_TRUE(status == 400 || status == 404) << target << " → " << status;
    EXPECT_EQ(answer.find("\r\n\r\nsecret"), std::string::npos) << target;
  }
}

}  // namespace
}  // namespace sf::web
