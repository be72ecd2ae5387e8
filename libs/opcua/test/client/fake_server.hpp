// A scripted OPC UA server on our own server transport, for client tests that need control over
// what a server does: it answers the session and subscription services itself, holds Publish
// requests until the test sends a notification, keeps messages for Republish, records every
// request, and can drop all connections (keeping or forgetting its sessions).
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sf/net/event_loop.hpp"
#include "sf/opcua/encoding.hpp"
#include "sf/opcua/transport/server_transport.hpp"

namespace sf::opcua::test {

class FakeServer : public ServiceHandler {
 public:
  // Answers a Read; nullopt → Good DataValue(Double 1.0) per node.
  using ReadHandler = std::function<std::optional<Message>(const ReadRequest&)>;

  FakeServer() = default;
  ~FakeServer() override { stop(); }
  FakeServer(const FakeServer&) = delete;
  FakeServer& operator=(const FakeServer&) = delete;

  bool start(std::uint16_t port = 0) {
    bool ok = false;
    thread_.run_sync([&] {
      ServerTransportConfig config;
      config.host = "127.0.0.1";
      config.port = port;
      auto transport = ServerTransport::start(thread_.loop(), config, *this);
      if (transport) {
        transport_ = std::move(*transport);
        port_ = transport_->port();
        ok = true;
      }
    });
    return ok;
  }
  // Closes the listener and every connection; sessions survive unless forget_sessions.
  void stop(bool forget_sessions = false) {
    thread_.run_sync([&] {
      if (transport_) {
        transport_->stop();
        transport_.reset();
      }
      std::lock_guard lock(mutex_);
      held_.clear();
      if (forget_sessions) {
        sessions_.clear();
      }
    });
  }
  // The server "restarts its session layer": every authentication token becomes unknown.
  void forget_sessions() {
    std::lock_guard lock(mutex_);
    sessions_.clear();
  }
  [[nodiscard]] std::string url() const { return "opc.tcp://127.0.0.1:" + std::to_string(port_); }
  [[nodiscard]] std::uint16_t port() const { return port_; }

  // The None endpoint also offers UserName logins with the secret encrypted for `certificate`
  // under `policy_uri`; CreateSession names no server certificate (as some servers do on a None
  // channel) but a server nonce of 32 bytes.
  void offer_user_name(ByteString certificate, std::string policy_uri) {
    std::lock_guard lock(mutex_);
    user_certificate_ = std::move(certificate);
    user_policy_uri_ = std::move(policy_uri);
  }
  static ByteString server_nonce() { return ByteString(Bytes(32, 0x5A)); }

  void set_read_handler(ReadHandler handler) {
    std::lock_guard lock(mutex_);
    read_handler_ = std::move(handler);
  }

  // ---- what the client sent ----
  std::vector<Message> requests() {
    std::lock_guard lock(mutex_);
    return requests_;
  }
  template <typename T>
  std::vector<T> requests_of() {
    std::lock_guard lock(mutex_);
    std::vector<T> out;
    for (const auto& m : requests_) {
      if (const auto* r = std::get_if<T>(&m)) {
        out.push_back(*r);
      }
    }
    return out;
  }
  // Waits until pred() holds (checked after every request and on each call).
  template <typename Pred>
  bool wait_until(Pred pred, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return pred(*this); });
  }
  // For predicates (the mutex is held).
  template <typename T>
  std::size_t count_locked() const {
    std::size_t n = 0;
    for (const auto& m : requests_) {
      n += std::holds_alternative<T>(m) ? 1U : 0U;
    }
    return n;
  }
  [[nodiscard]] std::size_t held_locked() const { return held_.size(); }
  [[nodiscard]] std::uint32_t last_subscription_id() {
    std::lock_guard lock(mutex_);
    return next_subscription_id_ - 1;
  }

  // ---- what the server sends ----
  // Answers one held Publish with a data change (value for client_handle) numbered sequence;
  // the message is kept for Republish. False if no Publish request is held.
  bool publish_data(std::uint32_t sequence, std::uint32_t client_handle, double value,
                    std::vector<std::uint32_t> available) {
    return publish(data_message(sequence, client_handle, value), std::move(available));
  }
  // A keep-alive announcing `next_sequence` as the next number.
  bool publish_keep_alive(std::uint32_t next_sequence, std::vector<std::uint32_t> available) {
    NotificationMessage message;
    message.sequence_number = next_sequence;
    message.publish_time = DateTime::from_system_clock(std::chrono::system_clock::now());
    return publish(std::move(message), std::move(available));
  }
  // Keeps a message for Republish without sending it (it was "lost on the way").
  void store_for_republish(std::uint32_t sequence, std::uint32_t client_handle, double value) {
    std::lock_guard lock(mutex_);
    retransmission_[sequence] = data_message(sequence, client_handle, value);
  }

  static NotificationMessage data_message(std::uint32_t sequence, std::uint32_t client_handle, double value) {
    NotificationMessage message;
    message.sequence_number = sequence;
    message.publish_time = DateTime::from_system_clock(std::chrono::system_clock::now());
    DataChangeNotification change;
    MonitoredItemNotification item;
    item.client_handle = client_handle;
    item.value = DataValue(Variant(value));
    change.monitored_items.push_back(item);
    message.notification_data.push_back(ExtensionObject::make(std::move(change)));
    return message;
  }

  // ---- ServiceHandler (loop thread) ----
  void on_request(const std::shared_ptr<ServerChannel>& channel, std::uint32_t request_id,
                  Message request) override {
    std::unique_lock lock(mutex_);
    requests_.push_back(request);
    std::optional<Message> response = answer(channel, request_id, request);
    cv_.notify_all();
    lock.unlock();
    if (response) {
      channel->send_response(request_id, *response);
    }
  }
  void on_channel_closed(std::uint32_t channel_id) override {
    std::lock_guard lock(mutex_);
    std::erase_if(held_, [&](const Held& h) { return h.channel->info().channel_id == channel_id; });
  }

 private:
  struct Held {
    std::shared_ptr<ServerChannel> channel;
    std::uint32_t request_id = 0;
    std::uint32_t request_handle = 0;
  };

  static ResponseHeader header_for(const RequestHeader& request, StatusCode result = {}) {
    ResponseHeader header;
    header.timestamp = DateTime::from_system_clock(std::chrono::system_clock::now());
    header.request_handle = request.request_handle;
    header.service_result = result;
    return header;
  }
  static Message fault(const RequestHeader& request, StatusCode code) {
    ServiceFault f;
    f.response_header = header_for(request, code);
    return f;
  }
  bool session_ok(const RequestHeader& header) const {
    return sessions_.count(to_string(header.authentication_token)) != 0;
  }

  std::optional<Message> answer(const std::shared_ptr<ServerChannel>& channel, std::uint32_t request_id,
                                const Message& request) {
    if (const auto* r = std::get_if<CreateSessionRequest>(&request)) {
      CreateSessionResponse response;
      response.response_header = header_for(r->request_header);
      const std::uint32_t n = next_session_++;
      response.session_id = NodeId(1, n);
      response.authentication_token = NodeId(1, String("token-" + std::to_string(n)));
      response.revised_session_timeout = r->requested_session_timeout;
      EndpointDescription endpoint;
      endpoint.endpoint_url = url();
      endpoint.security_mode = MessageSecurityMode::None;
      endpoint.security_policy_uri = "http://opcfoundation.org/UA/SecurityPolicy#None";
      UserTokenPolicy policy;
      policy.policy_id = "open-sesame";
      policy.token_type = UserTokenType::Anonymous;
      endpoint.user_identity_tokens.push_back(policy);
      if (!user_certificate_.empty()) {
        endpoint.server_certificate = user_certificate_;
        UserTokenPolicy user;
        user.policy_id = "user";
        user.token_type = UserTokenType::UserName;
        user.security_policy_uri = user_policy_uri_;
        endpoint.user_identity_tokens.push_back(user);
        response.server_nonce = server_nonce();
      }
      response.server_endpoints.push_back(endpoint);
      sessions_.insert(to_string(response.authentication_token));
      return response;
    }
    if (const auto* r = std::get_if<ActivateSessionRequest>(&request)) {
      if (!session_ok(r->request_header)) {
        return fault(r->request_header, status::BadSessionIdInvalid);
      }
      const auto* token = r->user_identity_token.get_if<AnonymousIdentityToken>();
      const auto* user = r->user_identity_token.get_if<UserNameIdentityToken>();
      const bool user_ok = user != nullptr && user->policy_id == "user" && !user_certificate_.empty();
      if (!user_ok && (token == nullptr || token->policy_id != "open-sesame")) {
        return fault(r->request_header, status::BadIdentityTokenInvalid);
      }
      ActivateSessionResponse response;
      response.response_header = header_for(r->request_header);
      return response;
    }
    if (const auto* r = std::get_if<CloseSessionRequest>(&request)) {
      sessions_.erase(to_string(r->request_header.authentication_token));
      CloseSessionResponse response;
      response.response_header = header_for(r->request_header);
      return response;
    }
    if (const auto* r = std::get_if<ReadRequest>(&request)) {
      if (!session_ok(r->request_header)) {
        return fault(r->request_header, status::BadSessionIdInvalid);
      }
      if (read_handler_) {
        if (auto custom = read_handler_(*r)) {
          return custom;
        }
      }
      ReadResponse response;
      response.response_header = header_for(r->request_header);
      for (std::size_t i = 0; i < r->nodes_to_read.size(); ++i) {
        response.results.push_back(DataValue(Variant(1.0)));
      }
      return response;
    }
    if (const auto* r = std::get_if<CreateSubscriptionRequest>(&request)) {
      CreateSubscriptionResponse response;
      response.response_header = header_for(r->request_header);
      response.subscription_id = next_subscription_id_++;
      response.revised_publishing_interval = r->requested_publishing_interval;
      response.revised_lifetime_count = r->requested_lifetime_count;
      response.revised_max_keep_alive_count = r->requested_max_keep_alive_count;
      return response;
    }
    if (const auto* r = std::get_if<CreateMonitoredItemsRequest>(&request)) {
      CreateMonitoredItemsResponse response;
      response.response_header = header_for(r->request_header);
      for (std::size_t i = 0; i < r->items_to_create.size(); ++i) {
        MonitoredItemCreateResult result;
        result.monitored_item_id = next_item_id_++;
        result.revised_sampling_interval = r->items_to_create[i].requested_parameters.sampling_interval;
        result.revised_queue_size = 1;
        response.results.push_back(result);
      }
      return response;
    }
    if (const auto* r = std::get_if<DeleteSubscriptionsRequest>(&request)) {
      DeleteSubscriptionsResponse response;
      response.response_header = header_for(r->request_header);
      response.results.assign(r->subscription_ids.size(), StatusCode());
      return response;
    }
    if (const auto* r = std::get_if<PublishRequest>(&request)) {
      held_.push_back(Held{channel, request_id, r->request_header.request_handle});
      return std::nullopt;
    }
    if (const auto* r = std::get_if<RepublishRequest>(&request)) {
      auto it = retransmission_.find(r->retransmit_sequence_number);
      if (it == retransmission_.end()) {
        return fault(r->request_header, status::BadMessageNotAvailable);
      }
      RepublishResponse response;
      response.response_header = header_for(r->request_header);
      response.notification_message = it->second;
      return response;
    }
    const RequestHeader* header = std::visit(
        [](const auto& m) -> const RequestHeader* {
          if constexpr (requires { m.request_header; }) {
            return &m.request_header;
          } else {
            return nullptr;
          }
        },
        request);
    return fault(header != nullptr ? *header : RequestHeader{}, status::BadServiceUnsupported);
  }

  bool publish(NotificationMessage message, std::vector<std::uint32_t> available) {
    bool sent = false;
    thread_.run_sync([&] {
      std::unique_lock lock(mutex_);
      if (held_.empty()) {
        return;
      }
      Held held = held_.front();
      held_.pop_front();
      if (!message.notification_data.empty()) {
        retransmission_[message.sequence_number] = message;
      }
      PublishResponse response;
      RequestHeader request;
      request.request_handle = held.request_handle;
      response.response_header = header_for(request);
      response.subscription_id = next_subscription_id_ - 1;
      response.available_sequence_numbers = available;
      response.notification_message = std::move(message);
      lock.unlock();
      held.channel->send_response(held.request_id, response);
      sent = true;
    });
    return sent;
  }

  net::LoopThread thread_;
  std::unique_ptr<ServerTransport> transport_;
  std::uint16_t port_ = 0;

  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<Message> requests_;
  std::set<std::string> sessions_;
  std::deque<Held> held_;
  std::map<std::uint32_t, NotificationMessage> retransmission_;
  ReadHandler read_handler_;
  ByteString user_certificate_;
  std::string user_policy_uri_;
  std::uint32_t next_session_ = 1;
  std::uint32_t next_subscription_id_ = 100;
  std::uint32_t next_item_id_ = 1;
};

}  // namespace sf::opcua::test
