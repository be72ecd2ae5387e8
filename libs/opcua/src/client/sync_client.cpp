// SyncClient: Client on its own LoopThread, each call waiting for its completion callback
// (which Client guarantees: every request has a timeout).
#include <future>
#include <memory>

#include "client_impl.hpp"

namespace sf::opcua {

struct SyncClient::Loop {
  net::LoopThread thread;
};

namespace {

// Starts an asynchronous call with a completion callback and waits for its result.
template <typename T, typename Start>
T wait_for(Start&& start) {
  auto promise = std::make_shared<std::promise<T>>();
  auto future = promise->get_future();
  start([promise](T result) { promise->set_value(std::move(result)); });
  return future.get();
}

}  // namespace

SyncClient::SyncClient(ClientConfig config) : loop_(std::make_unique<Loop>()) {
  client_ = std::make_unique<Client>(loop_->thread.loop(), std::move(config));
}

SyncClient::~SyncClient() {
  // Destroyed on the loop thread, while the loop still runs.
  loop_->thread.run_sync([this]() { client_.reset(); });
}

net::EventLoop& SyncClient::loop() {
  return loop_->thread.loop();
}

Status SyncClient::connect() {
  return wait_for<Status>([&](auto done) { client_->connect(std::move(done)); });
}

void SyncClient::disconnect() {
  auto promise = std::make_shared<std::promise<void>>();
  auto future = promise->get_future();
  client_->disconnect([promise]() { promise->set_value(); });
  future.wait();
}

void SyncClient::set_on_state(std::function<void(ClientState, const Status&)> on_state) {
  client_->set_on_state(std::move(on_state));
}

ClientState SyncClient::state() const {
  return client_->state();
}

Result<std::vector<DataValue>> SyncClient::read(std::vector<ReadValueId> nodes) {
  return wait_for<Result<std::vector<DataValue>>>(
      [&](auto done) { client_->read(std::move(nodes), std::move(done)); });
}

Result<std::vector<StatusCode>> SyncClient::write(std::vector<WriteValue> nodes) {
  return wait_for<Result<std::vector<StatusCode>>>(
      [&](auto done) { client_->write(std::move(nodes), std::move(done)); });
}

Result<std::vector<ReferenceDescription>> SyncClient::browse(BrowseDescription node) {
  return wait_for<Result<std::vector<ReferenceDescription>>>(
      [&](auto done) { client_->browse(std::move(node), std::move(done)); });
}

Result<std::vector<BrowsePathResult>> SyncClient::translate(std::vector<BrowsePath> paths) {
  return wait_for<Result<std::vector<BrowsePathResult>>>(
      [&](auto done) { client_->translate(std::move(paths), std::move(done)); });
}

Result<std::vector<CallMethodResult>> SyncClient::call(std::vector<CallMethodRequest> methods) {
  return wait_for<Result<std::vector<CallMethodResult>>>(
      [&](auto done) { client_->call(std::move(methods), std::move(done)); });
}

Result<std::vector<EndpointDescription>> SyncClient::get_endpoints() {
  return wait_for<Result<std::vector<EndpointDescription>>>(
      [&](auto done) { client_->get_endpoints(std::move(done)); });
}

Result<std::vector<ApplicationDescription>> SyncClient::find_servers(std::vector<std::string> server_uris) {
  return wait_for<Result<std::vector<ApplicationDescription>>>(
      [&](auto done) { client_->find_servers(std::move(server_uris), std::move(done)); });
}

Result<std::vector<DataValue>> SyncClient::history_read_raw(const NodeId& node, HistoryRawParams params) {
  return wait_for<Result<std::vector<DataValue>>>(
      [&](auto done) { client_->history_read_raw(node, params, std::move(done)); });
}

Result<SyncClient::SubscriptionId> SyncClient::create_subscription(SubscriptionParams params) {
  return wait_for<Result<SubscriptionId>>(
      [&](auto done) { client_->create_subscription(params, std::move(done)); });
}

Result<std::uint32_t> SyncClient::monitor_value(SubscriptionId subscription, ReadValueId item,
                                                MonitoringParameters parameters,
                                                Client::DataChangeCallback on_change) {
  return wait_for<Result<std::uint32_t>>([&](auto done) {
    client_->monitor_value(subscription, std::move(item), std::move(parameters), std::move(on_change),
                           std::move(done));
  });
}

Result<std::uint32_t> SyncClient::monitor_events(SubscriptionId subscription, NodeId notifier,
                                                 EventFilter filter, Client::EventCallback on_event) {
  return wait_for<Result<std::uint32_t>>([&](auto done) {
    client_->monitor_events(subscription, std::move(notifier), std::move(filter), std::move(on_event),
                            std::move(done));
  });
}

Status SyncClient::unmonitor(SubscriptionId subscription, std::uint32_t client_handle) {
  return wait_for<Status>(
      [&](auto done) { client_->unmonitor(subscription, client_handle, std::move(done)); });
}

Status SyncClient::delete_subscription(SubscriptionId subscription) {
  return wait_for<Status>([&](auto done) { client_->delete_subscription(subscription, std::move(done)); });
}

Result<DataValue> SyncClient::read_value(const NodeId& node) {
  auto values = read({value_of(node)});
  if (!values) {
    return client_detail::error_of(values);
  }
  DataValue& value = values->front();
  if (value.status.is_bad()) {
    return status_error(value.status, "Read " + to_string(node));
  }
  return std::move(value);
}

Status SyncClient::write_value(const NodeId& node, Variant value) {
  WriteValue write_value;
  write_value.node_id = node;
  write_value.attribute_id = attribute_id::Value;
  write_value.value = DataValue(std::move(value));
  auto results = write({std::move(write_value)});
  if (!results) {
    return client_detail::error_of(results);
  }
  if (results->front().is_bad()) {
    return status_error(results->front(), "Write " + to_string(node));
  }
  return {};
}

Result<std::vector<Variant>> SyncClient::call_method(const NodeId& object, const NodeId& method,
                                                     std::vector<Variant> inputs) {
  CallMethodRequest request;
  request.object_id = object;
  request.method_id = method;
  request.input_arguments = std::move(inputs);
  auto results = call({std::move(request)});
  if (!results) {
    return client_detail::error_of(results);
  }
  CallMethodResult& result = results->front();
  if (result.status_code.is_bad()) {
    return status_error(result.status_code, "Call " + to_string(method));
  }
  return std::vector<Variant>(std::make_move_iterator(result.output_arguments.begin()),
                              std::make_move_iterator(result.output_arguments.end()));
}

Result<std::uint16_t> SyncClient::namespace_index(std::string_view uri) {
  auto value = read_value(NodeId(0, id::Server_NamespaceArray));
  if (!value) {
    return client_detail::error_of(value);
  }
  const auto* names = value->value.array_if<String>();
  if (names == nullptr) {
    return status_error(status::BadTypeMismatch, "NamespaceArray is not an array of String");
  }
  for (std::size_t i = 0; i < names->size() && i <= UINT16_MAX; ++i) {
    if ((*names)[i] == uri) {
      return static_cast<std::uint16_t>(i);
    }
  }
  return status_error(status::BadNotFound, "namespace " + std::string(uri) + " not in the NamespaceArray");
}

Result<std::vector<ReferenceDescription>> SyncClient::browse_children(const NodeId& node) {
  return browse(browse_children_of(node));
}

}  // namespace sf::opcua
