// HTTPS and WSS (ServerConfig::tls) against Node.js's TLS clients (tests/peers/web/tls_client.mjs),
// which verify the server's certificate as a browser would: a request and a live subscription over
// TLS, TLS 1.2 with an AEAD cipher and nothing older, bytes that are not TLS refused while the
// server keeps serving, a stalled handshake closed, and the configurations start() refuses.
// Certificates are made at test time (sf/web/testing/tls_files.hpp).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "sf/core/process.hpp"
#include "sf/testing/node_peer.hpp"
#include "sf/web/server.hpp"
#include "sf/web/testing/client.hpp"
#include "sf/web/testing/tls_files.hpp"

namespace sf::web {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

using testing::TlsFiles;

TlsConfig tls_config() {
  const auto& files = TlsFiles::get();
  return {files.chain, files.key};
}

class TlsServer : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = sf::testing::node_unavailable()) {
      GTEST_SKIP() << *why;
    }
    if (!fs::exists(sf::testing::source_dir() / "node_modules" / "ws")) {
      GTEST_SKIP() << "node_modules/ws is missing (npm ci)";
    }
  }

  void start(TlsConfig tls = tls_config()) {
    ServerConfig config;
    config.idle_timeout_seconds = testing::kTestIdleTimeout;
    config.tls = std::move(tls);
    Router router;
    ASSERT_TRUE(router.add("GET", "/api/hello", [](const Request&) {
      return json_response({{"hello", "tls"}});
    }));
    server_ = std::make_unique<HttpServer>(std::move(config), std::move(router));
    auto port = server_->start();
    ASSERT_TRUE(port) << port.error().describe();
    port_ = *port;
  }

  ProcessOptions peer(const std::vector<std::string>& args) const {
    ProcessOptions o;
    o.argv = {sf::testing::find_node()->string(),
              (sf::testing::source_dir() / "tests" / "peers" / "web" / "tls_client.mjs").string()};
    o.argv.push_back(args.at(0));
    o.argv.push_back(std::to_string(port_));
    o.argv.push_back(TlsFiles::get().ca.string());
    o.argv.insert(o.argv.end(), args.begin() + 1, args.end());
    o.cwd = sf::testing::source_dir();
    o.out = Stdio::pipe();
    return o;
  }

  // One HTTPS GET by the node peer: its JSON line.
  nlohmann::json node_get(const std::vector<std::string>& args) const {
    auto done = Process::run(peer(args), 60s);
    if (!done) {
      ADD_FAILURE() << done.error().describe();
      return {};
    }
    return nlohmann::json::parse(done->out, nullptr, false);
  }

  void expect_hello(const nlohmann::json& answer) const {
    ASSERT_FALSE(answer.is_discarded());
    EXPECT_EQ(answer.value("status", 0), 200) << answer.dump();
    EXPECT_EQ(answer.value("body", ""), R"({"hello":"tls"})");
  }

  // A request by Beast's TLS client (sf::web_testing) is answered.
  void expect_still_serving() const {
    const auto response =
        testing::https_request(TlsFiles::get().ca, port_, boost::beast::http::verb::get, "/api/hello");
    EXPECT_EQ(response.result_int(), 200U);
    EXPECT_EQ(response.body(), R"({"hello":"tls"})");
  }

  std::unique_ptr<HttpServer> server_;
  std::uint16_t port_ = 0;
};

TEST_F(TlsServer, AnswersHttpsOverTls13WithStrictTransportSecurity) {
  start();
  const auto answer = node_get({"https", "/api/hello"});
  expect_hello(answer);
  EXPECT_EQ(answer.value("protocol", ""), "TLSv1.3");
  const auto& headers = answer.at("headers");
  EXPECT_EQ(headers.value("strict-transport-security", ""), "max-age=31536000");
  EXPECT_EQ(headers.value("content-security-policy", ""), "default-src 'self'");
  EXPECT_EQ(server_->stats().tls_failures, 0U);
}

TEST_F(TlsServer, AcceptsTls12WithForwardSecretAeadOnly) {
  start();
  const auto answer = node_get({"https", "/api/hello", R"({"maxVersion": "TLSv1.2"})"});
  expect_hello(answer);
  EXPECT_EQ(answer.value("protocol", ""), "TLSv1.2");
  const auto cipher = answer.value("cipher", "");
  EXPECT_TRUE(cipher.starts_with("TLS_ECDHE_")) << cipher;
  EXPECT_TRUE(cipher.find("_GCM_") != std::string::npos ||
              cipher.find("CHACHA20_POLY1305") != std::string::npos)
      << cipher;
}

// A client that offers only what the server does not take gets the alert that says why
// (RFC 8446 §6.2) and the server counts the failure.
TEST_F(TlsServer, RefusesTls11AndCiphersWithoutForwardSecrecyOrAead) {
  start();
  // OpenSSL offers TLS 1.1 at all only at its lowest security level.
  const auto tls11 =
      node_get({"https", "/api/hello",
                R"({"minVersion": "TLSv1.1", "maxVersion": "TLSv1.1", "ciphers": "DEFAULT@SECLEVEL=0"})"});
  EXPECT_NE(tls11.value("message", "").find("alert protocol version"), std::string::npos) << tls11.dump();
  const auto cbc =
      node_get({"https", "/api/hello",
                R"({"maxVersion": "TLSv1.2", "ciphers": "ECDHE-RSA-AES128-SHA:AES128-GCM-SHA256"})"});
  EXPECT_NE(cbc.value("message", "").find("alert handshake failure"), std::string::npos) << cbc.dump();
  testing::wait_until([&] { return server_->stats().tls_failures == 2; });
}

TEST_F(TlsServer, LiveUpdatesOverWss) {
  start();
  auto started = Process::spawn([&] {
    auto o = peer({"wss", "machine/M1"});
    o.in = Stdio::pipe();
    return o;
  }());
  ASSERT_TRUE(started) << started.error().describe();
  auto& client = *started;
  auto subscribed = client.read_line(60s);
  ASSERT_TRUE(subscribed) << subscribed.error().describe();
  EXPECT_EQ(nlohmann::json::parse(*subscribed), (nlohmann::json{{"subscribed", {"machine/M1"}}}));
  server_->publish("machine/M1", {{"state", "Execute"}});
  auto update = client.read_line(30s);
  ASSERT_TRUE(update) << update.error().describe();
  EXPECT_EQ(nlohmann::json::parse(*update),
            (nlohmann::json{{"topic", "machine/M1"}, {"value", {{"state", "Execute"}}}}));
  client.close_stdin();  // the peer closes with 1000; the server answers and tears TLS down
  auto closed = client.read_line(30s);
  ASSERT_TRUE(closed) << closed.error().describe();
  EXPECT_EQ(nlohmann::json::parse(*closed), (nlohmann::json{{"closed", 1000}}));
  testing::wait_until([&] { return server_->stats().connections == 0; });
  EXPECT_EQ(server_->stats().tls_failures, 0U);
}

TEST_F(TlsServer, GarbageAndPlainHttpAreRefusedAndServingGoesOn) {
  start();
  const auto garbage = testing::raw_exchange(port_, std::string(300, '\x5a'));
  EXPECT_EQ(testing::raw_status(garbage), 0);
  const auto plain = testing::raw_exchange(port_, "GET /api/hello HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(testing::raw_status(plain), 0) << "a plain HTTP answer on the TLS port";
  EXPECT_EQ(plain.find("hello"), std::string::npos);
  testing::wait_until([&] { return server_->stats().tls_failures == 2; });
  expect_still_serving();
  EXPECT_EQ(server_->stats().tls_failures, 2U);
}

TEST_F(TlsServer, StalledHandshakeIsClosedAfterItsTimeout) {
  auto tls = tls_config();
  tls.handshake_timeout_seconds = 1;
  start(tls);
  boost::asio::io_context context;
  auto socket = testing::connect(context, port_);  // connects, sends no ClientHello
  std::array<char, 64> buffer{};
  boost::system::error_code error;
  const auto n = socket.read_some(boost::asio::buffer(buffer), error);
  EXPECT_EQ(n, 0U);
  EXPECT_EQ(error, boost::asio::error::eof);
  testing::wait_until([&] { return server_->stats().tls_failures == 1; });
  expect_still_serving();
}

// start() refuses what it cannot serve, naming the file and the problem.
void expect_start_error(const TlsConfig& tls, const std::string& says) {
  ServerConfig config;
  config.tls = tls;
  HttpServer server(std::move(config), Router{});
  auto port = server.start();
  ASSERT_FALSE(port);
  EXPECT_NE(port.error().message.find(says), std::string::npos) << port.error().message;
}

TEST(TlsConfigErrors, StartSaysWhatIsWrongWithTheCertificateOrKey) {
  const auto& c = TlsFiles::get();
  expect_start_error({c.expired_chain, c.key}, c.expired_chain.string() + ": expired on ");
  expect_start_error({c.chain, c.other_key}, c.other_key.string() + ": does not match the certificate");
  expect_start_error({c.chain, c.dir.path() / "missing.pem"}, "missing.pem: No such file or directory");
  expect_start_error({c.dir.path() / "missing.pem", c.key}, "missing.pem: No such file or directory");
  expect_start_error({c.not_pem, c.key}, "not.pem: not a PEM certificate chain");
  expect_start_error({c.chain, c.not_pem}, "not.pem: not an unencrypted PEM private key");
  expect_start_error({c.chain, c.key, 0}, "handshake timeout");
}

}  // namespace
}  // namespace sf::web
