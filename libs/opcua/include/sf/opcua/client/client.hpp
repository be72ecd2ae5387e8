// The OPC UA client (OPC 10000-4 §5.4–§5.13, client side): an asynchronous Client on an
// sf::net::EventLoop and a blocking SyncClient on its own loop thread.
//
// Client: every public method may be called from any thread; it posts to the loop. Every
// completion callback runs on the loop thread, exactly once (unless the Client is destroyed
// first: then pending callbacks are dropped, not called). Errors carry the OPC UA StatusCode
// (status_of(error)): a ServiceFault or a Bad serviceResult becomes an error with that code;
// operation-level results (one per item) are returned as they are.
//
// Connection (OPC 10000-4 §6.7 "re-establishing connections"): connect() opens the secure
// channel, creates and activates a session (anonymous, with the policy id from the endpoint's
// UserTokenPolicy, or the configured user). With a security policy other than None it first
// asks the server for its endpoints over a None channel, picks one, checks the server's
// certificate, then opens the secured channel and checks the session signatures (§5.6.2). When the channel is
// lost and auto_reconnect is on, the client retries with exponential backoff (reconnect_min ..
// reconnect_max). On a new channel it first activates the existing session; if that works, subscriptions
// continue: missing notifications are fetched with Republish and Publish resumes. If the session is gone, a
// new session is created and every subscription and monitored item is re-created with the same client handles
// and callbacks (the initial values arrive again). Notifications are delivered per subscription in
// sequence-number order, without duplicates.
//
// Service requests made while not Connected fail with BadNotConnected.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/net/event_loop.hpp"
#include "sf/opcua/client/client_security.hpp"
#include "sf/opcua/encoding.hpp"
#include "sf/opcua/transport/tcp_messages.hpp"

namespace sf::opcua {

// Attribute ids used by client requests (OPC 10000-6 §A.1 / OPC 10000-3 §5.9).
namespace attribute_id {
inline constexpr std::uint32_t NodeId = 1;
inline constexpr std::uint32_t NodeClass = 2;
inline constexpr std::uint32_t BrowseName = 3;
inline constexpr std::uint32_t DisplayName = 4;
inline constexpr std::uint32_t Description = 5;
inline constexpr std::uint32_t EventNotifier = 12;
inline constexpr std::uint32_t Value = 13;
inline constexpr std::uint32_t DataType = 14;
inline constexpr std::uint32_t AccessLevel = 17;
}  // namespace attribute_id

struct ClientConfig {
  std::string endpoint_url;  // opc.tcp://host:port[/path]
  std::string application_name = "smartfactory client";
  std::string application_uri = "urn:smartfactory:client";
  std::string session_name = "smartfactory";
  double session_timeout_ms = 60'000;
  // Per request (also the connect timeout); Publish waits longer (see subscriptions).
  std::chrono::milliseconds request_timeout{10'000};
  bool auto_reconnect = true;
  std::chrono::milliseconds reconnect_min{250};
  std::chrono::milliseconds reconnect_max{10'000};
  std::size_t publish_requests = 3;  // outstanding Publish requests per session
  TransportLimits limits;
  // Endpoint selection, own certificate, server certificate checks (client_security.hpp); the
  // default is SecurityPolicy None without discovery.
  ClientSecurity security;
  UserIdentity user;  // anonymous by default
};

// A raw history read (OPC 10000-11 §6.4.3.2): [start, end) forwards, or backwards when
// start > end; with one bound open (DateTime::min()) max_values counts from the other.
struct HistoryRawParams {
  DateTime start;
  DateTime end;
  // numValuesPerNode: the values per response when both bounds are given (the client follows
  // continuation points until it has all), the number of values otherwise; 0 = all.
  std::uint32_t max_values = 0;
  bool return_bounds = false;
};

enum class ClientState : std::uint8_t { Disconnected, Connecting, Connected, Reconnecting };
std::string_view to_string(ClientState state);

class Client {
 public:
  using SubscriptionId = std::uint32_t;  // client-side handle, stable across reconnects
  struct SubscriptionParams {
    double publishing_interval_ms = 100;
    std::uint32_t lifetime_count = 1000;
    std::uint32_t max_keep_alive_count = 10;
    std::uint32_t max_notifications_per_publish = 0;
    std::uint8_t priority = 0;
  };
  using DataChangeCallback = std::function<void(const DataValue&)>;
  using EventCallback = std::function<void(const std::vector<Variant>& fields)>;
  // The client handle the client assigned to a new monitored item (unique per Client).
  using MonitorDone = std::function<void(Result<std::uint32_t>)>;

  Client(net::EventLoop& loop, ClientConfig config);
  // Closes the session and channel if open (best effort, nothing is awaited). Call it on the
  // loop thread, or on another thread while the loop is running (it waits for the loop).
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Opens the channel, CreateSession, ActivateSession. Fails (and stays Disconnected) if any
  // step fails; BadInvalidState unless Disconnected.
  void connect(std::function<void(Status)> done);
  // CloseSession(deleteSubscriptions = true), CLO; forgets all subscriptions. Always completes.
  void disconnect(std::function<void()> done);
  // Every state change, with the reason (an error for connection loss).
  void set_on_state(std::function<void(ClientState, const Status&)> on_state);

  void read(std::vector<ReadValueId> nodes, std::function<void(Result<std::vector<DataValue>>)> done);
  void write(std::vector<WriteValue> nodes, std::function<void(Result<std::vector<StatusCode>>)> done);
  // All references of one node: follows BrowseNext until the server has no more. A Bad status
  // of the node's BrowseResult is returned as an error.
  void browse(BrowseDescription node, std::function<void(Result<std::vector<ReferenceDescription>>)> done);
  void translate(std::vector<BrowsePath> paths,
                 std::function<void(Result<std::vector<BrowsePathResult>>)> done);
  void call(std::vector<CallMethodRequest> methods,
            std::function<void(Result<std::vector<CallMethodResult>>)> done);
  // The raw history of one Variable, following continuation points; a Bad status of the node's
  // HistoryReadResult is returned as an error.
  void history_read_raw(NodeId node, HistoryRawParams params,
                        std::function<void(Result<std::vector<DataValue>>)> done);
  // On the session's channel when connected; otherwise on a channel of its own (no session).
  void get_endpoints(std::function<void(Result<std::vector<EndpointDescription>>)> done);
  // FindServers (OPC 10000-4 §5.4.2): the servers a discovery server knows (a server: itself),
  // those with an ApplicationUri in server_uris when it is not empty. Like get_endpoints.
  void find_servers(std::vector<std::string> server_uris,
                    std::function<void(Result<std::vector<ApplicationDescription>>)> done);

  // Subscriptions (OPC 10000-4 §5.13): the client keeps publish_requests Publish requests
  // outstanding, acknowledges what it received and fills gaps in sequence numbers with
  // Republish.
  void create_subscription(SubscriptionParams params, std::function<void(Result<SubscriptionId>)> done);
  // A data-change monitored item (Reporting, timestamps Both). parameters.client_handle is
  // ignored: the client assigns one and reports it through done.
  void monitor_value(SubscriptionId subscription, ReadValueId item, MonitoringParameters parameters,
                     DataChangeCallback on_change, MonitorDone done);
  // An event monitored item on `notifier`'s EventNotifier attribute; the callback gets the
  // event's fields in the order of filter.select_clauses.
  void monitor_events(SubscriptionId subscription, NodeId notifier, EventFilter filter,
                      EventCallback on_event, MonitorDone done);
  // Deletes one monitored item of a subscription.
  void unmonitor(SubscriptionId subscription, std::uint32_t client_handle, std::function<void(Status)> done);
  // Deletes the subscription on the server (when connected) and forgets it.
  void delete_subscription(SubscriptionId subscription, std::function<void(Status)> done);

  [[nodiscard]] ClientState state() const;

  struct Impl;

 private:
  net::EventLoop& loop_;
  std::shared_ptr<Impl> impl_;
};

// A blocking facade over Client, running its own loop thread: the same operations returning
// their result synchronously (for the CLI and tests). Subscription callbacks and the state
// callback run on the internal loop thread. Not for use from inside those callbacks.
class SyncClient {
 public:
  using SubscriptionId = Client::SubscriptionId;
  using SubscriptionParams = Client::SubscriptionParams;

  explicit SyncClient(ClientConfig config);
  ~SyncClient();
  SyncClient(const SyncClient&) = delete;
  SyncClient& operator=(const SyncClient&) = delete;

  Status connect();
  void disconnect();
  void set_on_state(std::function<void(ClientState, const Status&)> on_state);
  [[nodiscard]] ClientState state() const;

  Result<std::vector<DataValue>> read(std::vector<ReadValueId> nodes);
  Result<std::vector<StatusCode>> write(std::vector<WriteValue> nodes);
  Result<std::vector<ReferenceDescription>> browse(BrowseDescription node);
  Result<std::vector<BrowsePathResult>> translate(std::vector<BrowsePath> paths);
  Result<std::vector<CallMethodResult>> call(std::vector<CallMethodRequest> methods);
  Result<std::vector<EndpointDescription>> get_endpoints();
  Result<std::vector<ApplicationDescription>> find_servers(std::vector<std::string> server_uris = {});
  Result<std::vector<DataValue>> history_read_raw(const NodeId& node, HistoryRawParams params);

  Result<SubscriptionId> create_subscription(SubscriptionParams params);
  Result<std::uint32_t> monitor_value(SubscriptionId subscription, ReadValueId item,
                                      MonitoringParameters parameters, Client::DataChangeCallback on_change);
  Result<std::uint32_t> monitor_events(SubscriptionId subscription, NodeId notifier, EventFilter filter,
                                       Client::EventCallback on_event);
  Status unmonitor(SubscriptionId subscription, std::uint32_t client_handle);
  Status delete_subscription(SubscriptionId subscription);

  // Conveniences over the calls above; a Bad operation-level status becomes the error.
  // The Value attribute of one node (a Bad DataValue status is returned as an error).
  Result<DataValue> read_value(const NodeId& node);
  Status write_value(const NodeId& node, Variant value);
  // Calls one method; returns its output arguments.
  Result<std::vector<Variant>> call_method(const NodeId& object, const NodeId& method,
                                           std::vector<Variant> inputs);
  // The index of a namespace URI in the server's NamespaceArray (Server_NamespaceArray);
  // BadNotFound if the server does not have it.
  Result<std::uint16_t> namespace_index(std::string_view uri);
  // Forward hierarchical references of a node (HierarchicalReferences with subtypes, all
  // node classes, all result fields).
  Result<std::vector<ReferenceDescription>> browse_children(const NodeId& node);

  Client& client() { return *client_; }
  net::EventLoop& loop();

 private:
  struct Loop;
  std::unique_ptr<Loop> loop_;
  std::unique_ptr<Client> client_;
};

// A BrowseDescription for the forward hierarchical references of node, all fields.
BrowseDescription browse_children_of(const NodeId& node);
// The Value attribute of node.
ReadValueId value_of(const NodeId& node);
// An EventFilter selecting BaseEventType fields by browse name ("EventId", "Message",
// "Severity", ...; "A/B" for a path), no where clause (OPC 10000-4 §7.22.3).
EventFilter select_event_fields(const std::vector<std::string>& base_event_fields);

}  // namespace sf::opcua
