// Client::Impl: the state of one OPC UA client, shared by the files of src/client. Everything in
// here runs on the loop thread; the public Client methods post to it.
//
//   session.cpp        connect, CreateSession/ActivateSession, request headers
//   connection.cpp     lost channels and reconnect (OPC 10000-4 §6.7), keep-alive, disconnect
//   services.cpp       Read, Write, Browse(+Next), TranslateBrowsePaths, Call, GetEndpoints
//   subscriptions.cpp  CreateSubscription, monitored items, re-creation on a new session
//   publish.cpp        the Publish loop, acknowledgements, sequence numbers, Republish, delivery
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

#include "sf/core/log.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/transport/client_transport.hpp"

namespace sf::opcua::client_detail {

// The error of a failed Result, copied member by member: GCC 12 reports a false
// -Wmaybe-uninitialized for the defaulted copy of an Error held in Result's std::variant.
template <typename T>
Error error_of(const Result<T>& result) {
  const Error& error = result.error();
  Error copy(error.code, error.message);
  copy.protocol_code = error.protocol_code;
  return copy;
}

// The response type of each request the client sends.
template <typename Request>
struct ResponseOf;
#define SF_OPCUA_CLIENT_PAIR(Name)   \
  template <>                        \
  struct ResponseOf<Name##Request> { \
    using type = Name##Response;     \
  };
SF_OPCUA_CLIENT_PAIR(GetEndpoints)
SF_OPCUA_CLIENT_PAIR(FindServers)
SF_OPCUA_CLIENT_PAIR(CreateSession)
SF_OPCUA_CLIENT_PAIR(ActivateSession)
SF_OPCUA_CLIENT_PAIR(CloseSession)
SF_OPCUA_CLIENT_PAIR(Browse)
SF_OPCUA_CLIENT_PAIR(BrowseNext)
SF_OPCUA_CLIENT_PAIR(TranslateBrowsePathsToNodeIds)
SF_OPCUA_CLIENT_PAIR(Read)
SF_OPCUA_CLIENT_PAIR(Write)
SF_OPCUA_CLIENT_PAIR(Call)
SF_OPCUA_CLIENT_PAIR(HistoryRead)
SF_OPCUA_CLIENT_PAIR(CreateSubscription)
SF_OPCUA_CLIENT_PAIR(DeleteSubscriptions)
SF_OPCUA_CLIENT_PAIR(CreateMonitoredItems)
SF_OPCUA_CLIENT_PAIR(DeleteMonitoredItems)
SF_OPCUA_CLIENT_PAIR(Publish)
SF_OPCUA_CLIENT_PAIR(Republish)
#undef SF_OPCUA_CLIENT_PAIR

// Turns what the channel delivered into the expected response: a ServiceFault or a Bad
// serviceResult becomes an error with that StatusCode (OPC 10000-4 §7.34), another message type
// BadUnknownResponse.
template <typename Response>
Result<Response> unwrap_response(Result<Message> message, std::string_view request_name) {
  if (!message) {
    return error_of(message);
  }
  if (const auto* fault = std::get_if<ServiceFault>(&*message)) {
    const StatusCode code = fault->response_header.service_result;
    return status_error(code.is_bad() ? code : status::BadUnknownResponse,
                        std::string(request_name) + ": ServiceFault");
  }
  auto* response = std::get_if<Response>(&*message);
  if (response == nullptr) {
    return status_error(status::BadUnknownResponse, std::string(request_name) + ": unexpected response " +
                                                        std::string(message_type_name(*message)));
  }
  if (response->response_header.service_result.is_bad()) {
    return status_error(response->response_header.service_result, std::string(request_name) + " failed");
  }
  return std::move(*response);
}

// Errors that mean the channel (not the server) failed: the request may not have arrived.
bool is_transport_error(StatusCode code);
// Errors that mean the server no longer knows the session (OPC 10000-4 §5.6.3, §6.7).
bool is_session_error(StatusCode code);

// Sequence numbers (OPC 10000-4 §7.38... §5.13.1.1): UInt32 starting at 1, rolling over to 1
// after 4294967295, never 0. Serial comparison so that a roll-over orders correctly.
inline std::uint32_t next_sequence(std::uint32_t n) {
  return n == UINT32_MAX ? 1U : n + 1U;
}
inline bool sequence_before(std::uint32_t a, std::uint32_t b) {
  return static_cast<std::int32_t>(a - b) < 0;
}

}  // namespace sf::opcua::client_detail

namespace sf::opcua {

struct Client::Impl : std::enable_shared_from_this<Client::Impl> {
  struct MonitoredItem {
    std::uint32_t client_handle = 0;
    ReadValueId item;
    MonitoringParameters parameters;  // client_handle filled in
    DataChangeCallback on_change;     // one of the two
    EventCallback on_event;
    std::uint32_t server_id = 0;
    bool created = false;  // the CreateMonitoredItems that added it succeeded
  };
  struct Subscription {
    SubscriptionId id = 0;
    SubscriptionParams params;
    std::uint32_t server_id = 0;  // 0: not (yet) on the server
    double revised_interval_ms = 0;
    std::uint32_t revised_keep_alive = 0;
    std::map<std::uint32_t, MonitoredItem> items;  // by client handle
    // Delivery in sequence-number order (OPC 10000-4 §5.13.1.1): the last delivered number
    // (0 before the first), messages that arrived ahead of a gap, numbers being republished
    // and numbers the server no longer has.
    std::uint32_t last_delivered = 0;
    std::map<std::uint32_t, NotificationMessage> ahead;
    std::set<std::uint32_t> republishing;
    std::set<std::uint32_t> lost;
    Array<std::uint32_t> last_available;  // availableSequenceNumbers of the last response
  };
  struct Session {
    NodeId session_id;
    NodeId authentication_token;
    double revised_timeout_ms = 0;
    std::string anonymous_policy_id;
    bool activated = false;
    // From CreateSession (the server's certificate) and the last CreateSession or
    // ActivateSession (the nonce the next ActivateSession signs, OPC 10000-4 §5.6.3).
    ByteString server_certificate;
    ByteString server_nonce;
  };

  Impl(net::EventLoop& loop, ClientConfig config);

  // ---- requests (session.cpp) ----
  // Fills the RequestHeader (OPC 10000-4 §7.33) and sends on the current channel; done gets
  // the typed response or an error, never from inside send(). Without a channel:
  // BadNotConnected. A session error while connected starts session recovery.
  template <typename Request>
  void send(Request request, std::chrono::milliseconds timeout,
            std::function<void(Result<typename client_detail::ResponseOf<Request>::type>)> done);
  template <typename Request>
  void send(Request request,
            std::function<void(Result<typename client_detail::ResponseOf<Request>::type>)> done) {
    send(std::move(request), config.request_timeout, std::move(done));
  }
  RequestHeader make_header(std::chrono::milliseconds timeout);
  // Posts fn to the loop unless the client is shut down.
  void post(std::function<void()> fn);
  // Posts done(error): keeps callbacks out of the caller's stack.
  template <typename T>
  void fail_later(std::function<void(Result<T>)> done, Error error) {
    post([done = std::move(done), error = std::move(error)]() { done(error); });
  }
  // BadNotConnected unless a session is usable.
  [[nodiscard]] std::optional<Error> check_connected(std::string_view what) const;

  // ---- connection and session (session.cpp, connection.cpp) ----
  void connect(std::function<void(Status)> done);
  void disconnect(std::function<void()> done);
  void shutdown();
  void set_state(ClientState next, const Status& reason);
  void open_channel();
  void on_channel_open(std::uint64_t generation, Result<std::shared_ptr<ClientChannel>> channel);
  void create_session();
  void activate_session(bool reactivating);
  void on_session_active(bool reactivated);
  void finish_connect();
  // The channel of `generation` failed or closed: reconnect, or report the failed connect.
  void lose_channel(std::uint64_t generation, const Error& error);
  void drop_channel();
  void schedule_reconnect();
  void start_keep_alive();
  void stop_timers();
  void forget_session();

  // ---- services (services.cpp) ----
  void read(std::vector<ReadValueId> nodes, std::function<void(Result<std::vector<DataValue>>)> done);
  void write(std::vector<WriteValue> nodes, std::function<void(Result<std::vector<StatusCode>>)> done);
  void browse(BrowseDescription node, std::function<void(Result<std::vector<ReferenceDescription>>)> done);
  void translate(std::vector<BrowsePath> paths,
                 std::function<void(Result<std::vector<BrowsePathResult>>)> done);
  void call(std::vector<CallMethodRequest> methods,
            std::function<void(Result<std::vector<CallMethodResult>>)> done);
  void browse_next(ByteString continuation_point, std::vector<ReferenceDescription> collected,
                   std::function<void(Result<std::vector<ReferenceDescription>>)> done);
  void get_endpoints(std::function<void(Result<std::vector<EndpointDescription>>)> done);
  void find_servers(std::vector<std::string> server_uris,
                    std::function<void(Result<std::vector<ApplicationDescription>>)> done);
  template <typename Response, typename Request>
  void discovery_request(Request request, std::function<void(Result<Response>)> finish);

  // ---- security (secure_session.cpp) ----
  // Policy None/None and no discovery (GetEndpoints is skipped).
  [[nodiscard]] bool plain() const;
  // GetEndpoints over a None channel, then the endpoint to use with its certificate checked.
  void discover_endpoint(std::uint64_t generation, std::function<void(Result<EndpointDescription>)> done);
  [[nodiscard]] ClientTransportConfig transport_config() const;
  void open_transport(std::uint64_t generation, ClientTransportConfig transport);
  // CreateSession: our certificate and nonce; the answer's signature and endpoints.
  void secure_create_request(CreateSessionRequest& request);
  Status check_create_response(const CreateSessionResponse& response);
  // ActivateSession: our signature and the user identity token.
  Status fill_activation(ActivateSessionRequest& request) const;
  [[nodiscard]] Status check_token_certificate(const ByteString& certificate,
                                               std::string_view channel_policy) const;

  // ---- history (history.cpp) ----
  void history_read_raw(NodeId node, HistoryRawParams params, std::vector<DataValue> collected,
                        ByteString continuation_point,
                        std::function<void(Result<std::vector<DataValue>>)> done);

  // ---- subscriptions (subscriptions.cpp) ----
  void create_subscription(SubscriptionParams params, std::function<void(Result<SubscriptionId>)> done);
  void add_monitored_item(SubscriptionId subscription, MonitoredItem item, MonitorDone done);
  void unmonitor(SubscriptionId subscription, std::uint32_t client_handle, std::function<void(Status)> done);
  void delete_subscription(SubscriptionId subscription, std::function<void(Status)> done);
  // New session: every subscription and its created items again (same client handles).
  void recreate_subscriptions(std::function<void()> done);
  void recreate_subscription(SubscriptionId id, std::function<void()> done);
  void recreate_items(SubscriptionId id, std::function<void()> done);
  static CreateSubscriptionRequest subscription_request(const SubscriptionParams& params);

  // ---- publishing (publish.cpp) ----
  void pump_publish();
  void send_publish();
  void on_publish(Result<PublishResponse> response);
  void on_notification(Subscription& sub, const NotificationMessage& message,
                       const Array<std::uint32_t>& available);
  // Sequence numbers from `from` up to (not including) `to` are missing: Republish the ones
  // the server still has, give up on the others.
  void fill_gap(Subscription& sub, std::uint32_t from, std::uint32_t to,
                const Array<std::uint32_t>& available);
  void republish(Subscription& sub, std::uint32_t sequence_number);
  void flush(Subscription& sub);
  void deliver(Subscription& sub, const NotificationMessage& message);
  // After ActivateSession on a new channel: Republish what was announced but not received.
  void republish_missing();
  [[nodiscard]] std::chrono::milliseconds publish_timeout() const;
  [[nodiscard]] bool has_server_subscription() const;
  Subscription* find_by_server_id(std::uint32_t server_id);

  net::EventLoop& loop;
  ClientConfig config;
  log::Logger logger;

  ClientState state = ClientState::Disconnected;
  std::atomic<ClientState> state_mirror{ClientState::Disconnected};
  std::function<void(ClientState, const Status&)> on_state;
  bool shut_down = false;
  bool disconnecting = false;

  std::shared_ptr<ClientChannel> channel;
  // Bumped whenever a channel is opened or dropped; callbacks of older channels are ignored.
  std::uint64_t channel_generation = 0;
  std::optional<Session> session;
  // The endpoint in use and what GetEndpoints listed (empty for None without discovery), and
  // the nonce of the last CreateSession.
  std::optional<EndpointDescription> endpoint;
  std::vector<EndpointDescription> discovered;
  ByteString client_nonce;
  // Bumped for every new session: subscription state of an older session is stale.
  std::uint64_t session_epoch = 0;
  std::uint32_t next_request_handle = 1;

  std::function<void(Status)> connect_done;
  net::EventLoop::TimerId reconnect_timer = 0;
  std::chrono::milliseconds backoff{0};
  net::EventLoop::TimerId keep_alive_timer = 0;

  std::map<SubscriptionId, Subscription> subscriptions;
  SubscriptionId next_subscription_id = 1;
  std::uint32_t next_client_handle = 1;
  std::size_t publish_outstanding = 0;
  std::size_t publish_target = 0;
  net::EventLoop::TimerId publish_retry_timer = 0;
  std::vector<SubscriptionAcknowledgement> pending_acks;
};

template <typename Request>
void Client::Impl::send(Request request, std::chrono::milliseconds timeout,
                        std::function<void(Result<typename client_detail::ResponseOf<Request>::type>)> done) {
  using Response = typename client_detail::ResponseOf<Request>::type;
  if (!channel) {
    fail_later(std::move(done),
               status_error(status::BadNotConnected, std::string(Request::kTypeName) + ": not connected"));
    return;
  }
  request.request_header = make_header(timeout);
  if constexpr (std::is_same_v<Request, GetEndpointsRequest>) {
    request.request_header.authentication_token = NodeId();  // a discovery service: no session
  }
  const std::uint64_t generation = channel_generation;
  const bool uses_session = !request.request_header.authentication_token.is_null();
  channel->send_request(
      Message(std::move(request)), timeout,
      [weak = weak_from_this(), generation, uses_session, done = std::move(done)](Result<Message> message) {
        auto self = weak.lock();
        if (!self || self->shut_down) {
          return;
        }
        auto response = client_detail::unwrap_response<Response>(std::move(message), Request::kTypeName);
        if (!response) {
          const StatusCode code = status_of(response.error());
          self->logger->debug("opcua client: {} failed: {}", Request::kTypeName, response.error().message);
          if (uses_session && client_detail::is_session_error(code) &&
              self->state == ClientState::Connected && !self->disconnecting &&
              generation == self->channel_generation) {
            // The server forgot the session (timeout, restart): recover it like a lost channel.
            self->post([weak, generation, error = client_detail::error_of(response)]() {
              if (auto s = weak.lock()) {
                s->lose_channel(generation, error);
              }
            });
          }
        }
        done(std::move(response));
      });
}

}  // namespace sf::opcua
