// HttpServer: HTTP/1.1 (RFC 9110, RFC 9112) and one WebSocket endpoint (RFC 6455) on
// Boost.Beast, with its own io_context threads; over TLS (HTTPS, WSS) when configured. Requests go to a
// Router, then to static files; the WebSocket endpoint carries live updates by topic (sf/web/live.hpp
// describes the protocol).
//
// Concurrency: start() and stop() from one owning thread; publish() and stats() from any
// thread. Handlers run on the server's threads and must not block for long.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "sf/core/result.hpp"
#include "sf/web/router.hpp"

namespace sf::web {

// Which topics one live client may subscribe to.
using TopicFilter = std::function<bool(std::string_view topic)>;
// The decision on a live endpoint's upgrade request (its cookies, its Origin): the client's topic
// filter, or the response sent instead of the upgrade (401, 403).
using LiveAccess = std::variant<TopicFilter, Response>;

// HTTPS and WSS instead of plain HTTP on the server's port (RFC 9110 §4.2.2): TLS 1.3, or 1.2 with
// forward-secret AEAD ciphers only (RFC 9325 §4.1, §4.2).
struct TlsConfig {
  std::filesystem::path certificate_chain;  // PEM: the server's certificate, then its issuers
  std::filesystem::path private_key;        // PEM, unencrypted (PKCS#8 or traditional)
  int handshake_timeout_seconds = 10;       // a peer that has not finished the handshake is closed
};

struct ServerConfig {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;  // 0: any free port, reported by start()
  int threads = 1;
  // Static files (GET/HEAD); empty: none.
  std::filesystem::path static_root;
  // The WebSocket endpoint of live updates; empty: none.
  std::string live_path = "/api/live";
  // Who may open the live endpoint and subscribe to what; empty: everyone, every topic. A topic
  // the filter refuses is answered {"error": "not allowed", "topics": [...]} and not subscribed.
  std::function<LiveAccess(const Request& upgrade)> live_access;
  // Set: every connection is TLS; start() fails on a certificate or key it cannot use.
  std::optional<TlsConfig> tls;

  // Limits: what a peer may make the server hold.
  std::size_t body_limit = 64UL * 1024UL;          // larger request bodies: 413 (RFC 9110 §15.5.14)
  std::size_t header_limit = 8UL * 1024UL;         // larger header sections: 431 (RFC 6585 §5)
  std::size_t max_connections = 256;               // more at once: 503 and close (RFC 9110 §15.6.4)
  std::size_t live_message_limit = 16UL * 1024UL;  // larger WebSocket messages: close 1009
  std::size_t live_topic_limit = 256;              // topics per live client (bounds its queue)
  int idle_timeout_seconds = 30;                   // a connection that sends nothing is closed
};

// Counters of one live (WebSocket) client.
struct LiveClientStats {
  std::uint64_t id = 0;
  std::size_t topics = 0;     // subscribed
  std::size_t pending = 0;    // topics with a value not yet written
  std::uint64_t sent = 0;     // updates written
  std::uint64_t dropped = 0;  // updates replaced by a newer value of their topic unsent
};

struct ServerStats {
  std::size_t connections = 0;            // open now (HTTP and WebSocket)
  std::uint64_t requests = 0;             // HTTP requests answered
  std::uint64_t refused_connections = 0;  // over max_connections
  std::uint64_t tls_failures = 0;         // TLS handshakes that failed or timed out (closed)
  std::vector<LiveClientStats> live_clients;
};

class HttpServer {
 public:
  HttpServer(ServerConfig config, Router router);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Loads the TLS certificate and key (if any), binds and listens, starts the threads; the port
  // listened on.
  Result<std::uint16_t> start();
  // Closes the listener and every connection, joins the threads. Idempotent.
  void stop();

  // Sends {"topic": topic, "value": value} to every live client subscribed to the topic. A
  // client still writing an earlier value of the topic gets only the latest one.
  void publish(const std::string& topic, const nlohmann::json& value);

  [[nodiscard]] ServerStats stats() const;

  class Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf::web
