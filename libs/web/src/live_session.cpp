#include "live_session.hpp"

#include <boost/asio/post.hpp>
#include <utility>

#include "live_protocol.hpp"

namespace sf::web {
namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = boost::beast::websocket;

namespace {

// Answers to the client's own messages that may wait unsent; a client that keeps asking
// without reading is closed with 1008 (RFC 6455 §7.4.1, policy violation).
constexpr std::size_t kMaxReplies = 64;

std::shared_ptr<const std::string> dump(const nlohmann::json& message) {
  return std::make_shared<const std::string>(
      message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

}  // namespace

LiveSession::LiveSession(Stream&& stream, std::shared_ptr<LiveHub> hub, const ServerConfig& config,
                         std::shared_ptr<ConnectionSlot> slot, TopicFilter filter)
    : ws_(std::move(stream)),
      hub_(std::move(hub)),
      config_(config),
      slot_(std::move(slot)),
      id_(hub_->next_id()),
      filter_(std::move(filter)) {}

void LiveSession::run(const beast::http::request<beast::http::string_body>& request) {
  beast::get_lowest_layer(ws_).expires_never();  // the WebSocket layer keeps its own timeouts
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.read_message_max(config_.live_message_limit);
  ws_.text(true);
  ws_.async_accept(request,
                   [self = shared_from_this()](const beast::error_code& error) { self->on_accept(error); });
}

void LiveSession::on_accept(const beast::error_code& error) {
  if (error) {
    return;
  }
  hub_->add(shared_from_this());
  read_next();
}

void LiveSession::read_next() {
  ws_.async_read(buffer_, [self = shared_from_this()](const beast::error_code& error, std::size_t) {
    self->on_read(error);
  });
}

void LiveSession::on_read(const beast::error_code& error) {
  if (error) {
    // A protocol violation (RFC 6455 §7.1.7) or an oversized message was answered with a
    // close frame by Beast already (1002, 1009); a closed connection needs nothing.
    finish();
    return;
  }
  if (!ws_.got_text()) {
    // RFC 6455 §7.4.1: 1003, a data type the endpoint cannot accept.
    ws_.async_close(websocket::close_reason(websocket::close_code::unknown_data, "only text messages"),
                    [self = shared_from_this()](const beast::error_code&) { self->finish(); });
    return;
  }
  handle_text(beast::buffers_to_string(buffer_.data()));
  buffer_.consume(buffer_.size());
  read_next();
}

void LiveSession::handle_text(const std::string& text) {
  auto request = parse_live_request(text);
  if (!request) {
    reply({{"error", request.error().message}});
    return;
  }
  const bool subscribe = request->kind == LiveRequest::Kind::subscribe;
  nlohmann::json current = nlohmann::json::array();
  nlohmann::json refused = nlohmann::json::array();
  bool over_limit = false;
  {
    std::lock_guard lock(mutex_);
    for (const auto& topic : request->topics) {
      if (subscribe && filter_ && !filter_(topic)) {
        refused.push_back(topic);
      } else if (!subscribe) {
        topics_.erase(topic);
        pending_.erase(topic);
        std::erase(pending_order_, topic);
      } else if (topics_.size() < config_.live_topic_limit || topics_.contains(topic)) {
        topics_.insert(topic);
      } else {
        over_limit = true;
      }
    }
    for (const auto& topic : topics_) {
      current.push_back(topic);
    }
  }
  if (!refused.empty()) {
    reply({{"error", "not allowed"}, {"topics", std::move(refused)}});
  }
  if (over_limit) {
    reply({{"error", "topic limit reached"}, {"limit", config_.live_topic_limit}});
  }
  reply({{"subscribed", std::move(current)}});
}

void LiveSession::reply(const nlohmann::json& message) {
  std::lock_guard lock(mutex_);
  if (replies_.size() >= kMaxReplies) {
    closed_ = true;
    ws_.async_close(websocket::close_reason(websocket::close_code::policy_error, "replies not read"),
                    [self = shared_from_this()](const beast::error_code&) { self->finish(); });
    return;
  }
  replies_.push_back(dump(message));
  kick_writer();
}

void LiveSession::enqueue(const std::string& topic, const std::shared_ptr<const std::string>& message) {
  std::lock_guard lock(mutex_);
  if (closed_ || !topics_.contains(topic)) {
    return;
  }
  auto [it, added] = pending_.try_emplace(topic, message);
  if (added) {
    pending_order_.push_back(topic);
  } else {
    it->second = message;  // coalesced: the earlier value is never sent
    ++dropped_;
  }
  kick_writer();
}

void LiveSession::kick_writer() {
  if (!writing_ && !closed_) {
    writing_ = true;
    net::post(ws_.get_executor(), [self = shared_from_this()] { self->write_next(); });
  }
}

void LiveSession::write_next() {
  {
    std::lock_guard lock(mutex_);
    if (closed_) {
      writing_ = false;
      return;
    }
    if (!replies_.empty()) {
      in_flight_ = std::move(replies_.front());
      replies_.pop_front();
    } else if (!pending_order_.empty()) {
      auto node = pending_.extract(pending_order_.front());
      pending_order_.pop_front();
      in_flight_ = std::move(node.mapped());
    } else {
      writing_ = false;
      return;
    }
  }
  ws_.async_write(net::buffer(*in_flight_),
                  [self = shared_from_this()](const beast::error_code& error, std::size_t) {
                    if (error) {
                      self->finish();
                      return;
                    }
                    {
                      std::lock_guard lock(self->mutex_);
                      ++self->sent_;
                    }
                    self->write_next();
                  });
}

void LiveSession::finish() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  hub_->remove(id_);
}

LiveClientStats LiveSession::stats() const {
  std::lock_guard lock(mutex_);
  return {id_, topics_.size(), pending_.size(), sent_, dropped_};
}

void LiveHub::add(const std::shared_ptr<LiveSession>& session) {
  std::lock_guard lock(mutex_);
  sessions_[session->id()] = session;
}

void LiveHub::remove(std::uint64_t id) {
  std::lock_guard lock(mutex_);
  sessions_.erase(id);
}

std::vector<std::shared_ptr<LiveSession>> LiveHub::sessions() const {
  std::vector<std::shared_ptr<LiveSession>> out;
  std::lock_guard lock(mutex_);
  for (const auto& [id, weak] : sessions_) {
    if (auto session = weak.lock()) {
      out.push_back(std::move(session));
    }
  }
  return out;
}

void LiveHub::publish(const std::string& topic, const nlohmann::json& value) {
  const auto message = dump({{"topic", topic}, {"value", value}});
  for (const auto& session : sessions()) {
    session->enqueue(topic, message);
  }
}

std::vector<LiveClientStats> LiveHub::stats() const {
  std::vector<LiveClientStats> out;
  for (const auto& session : sessions()) {
    out.push_back(session->stats());
  }
  return out;
}

}  // namespace sf::web
