// The live endpoint (RFC 6455): a client sends {"subscribe": ["topic", ...]} or
// {"unsubscribe": [...]} as text messages and receives {"topic": t, "value": v} for each
// published value of its topics. Replies: {"subscribed": [...]}, {"error": "..."}.
//
// Each client's queue holds at most one value per subscribed topic: a value published while
// an earlier one of the same topic waits replaces it (counted as dropped), so a slow client
// costs the server a bounded amount of memory and always gets the latest value.
#pragma once

#include <atomic>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "sf/web/server.hpp"
#include "stream.hpp"

namespace sf::web {

class ConnectionSlot;
class LiveHub;

class LiveSession : public std::enable_shared_from_this<LiveSession> {
 public:
  // filter: the topics this client may subscribe to (empty: all).
  LiveSession(Stream&& stream, std::shared_ptr<LiveHub> hub, const ServerConfig& config,
              std::shared_ptr<ConnectionSlot> slot, TopicFilter filter = {});

  // Completes the opening handshake (RFC 6455 §4.2.2) for the upgrade request.
  void run(const boost::beast::http::request<boost::beast::http::string_body>& request);
  // Queues a value of a topic when the client subscribed to it; any thread.
  void enqueue(const std::string& topic, const std::shared_ptr<const std::string>& message);
  [[nodiscard]] LiveClientStats stats() const;
  [[nodiscard]] std::uint64_t id() const { return id_; }

 private:
  void on_accept(const boost::beast::error_code& error);
  void read_next();
  void on_read(const boost::beast::error_code& error);
  void handle_text(const std::string& text);
  void reply(const nlohmann::json& message);
  void kick_writer();  // with mutex_ held
  void write_next();
  void finish();

  boost::beast::websocket::stream<Stream> ws_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<LiveHub> hub_;
  const ServerConfig& config_;
  std::shared_ptr<ConnectionSlot> slot_;
  const std::uint64_t id_;

  mutable std::mutex mutex_;
  std::set<std::string> topics_;
  TopicFilter filter_;
  std::deque<std::string> pending_order_;  // topics with a queued value, oldest first
  std::map<std::string, std::shared_ptr<const std::string>> pending_;
  std::deque<std::shared_ptr<const std::string>> replies_;  // answers to the client's own messages, in order
  bool writing_ = false;
  bool closed_ = false;
  std::uint64_t sent_ = 0;
  std::uint64_t dropped_ = 0;
  std::shared_ptr<const std::string> in_flight_;
};

// The set of live clients and publication to them.
class LiveHub {
 public:
  void add(const std::shared_ptr<LiveSession>& session);
  void remove(std::uint64_t id);
  void publish(const std::string& topic, const nlohmann::json& value);
  [[nodiscard]] std::vector<LiveClientStats> stats() const;
  std::uint64_t next_id() { return ++last_id_; }

 private:
  [[nodiscard]] std::vector<std::shared_ptr<LiveSession>> sessions() const;

  mutable std::mutex mutex_;
  std::map<std::uint64_t, std::weak_ptr<LiveSession>> sessions_;
  std::atomic<std::uint64_t> last_id_{0};
};

// One counted connection: taken on accept, released when the last owner (the HTTP session,
// then the live session it became) goes away.
class ConnectionSlot {
 public:
  explicit ConnectionSlot(std::atomic<std::size_t>& open) : open_(open) { ++open_; }
  ~ConnectionSlot() { --open_; }
  ConnectionSlot(const ConnectionSlot&) = delete;
  ConnectionSlot& operator=(const ConnectionSlot&) = delete;

 private:
  std::atomic<std::size_t>& open_;
};

}  // namespace sf::web
