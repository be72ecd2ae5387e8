// Client's public methods: each posts its work to the loop thread (so they may be called from
// any thread and never re-enter the client from inside one of its callbacks).
#include <future>

#include "client_impl.hpp"

namespace sf::opcua {

std::string_view to_string(ClientState state) {
  switch (state) {
    case ClientState::Disconnected:
      return "Disconnected";
    case ClientState::Connecting:
      return "Connecting";
    case ClientState::Connected:
      return "Connected";
    case ClientState::Reconnecting:
      return "Reconnecting";
  }
  return "ClientState(?)";
}

namespace {

// Runs fn(impl) on the loop thread unless the client was destroyed meanwhile.
template <typename Fn>
void post_to(net::EventLoop& loop, const std::shared_ptr<Client::Impl>& impl, Fn fn) {
  loop.post([weak = std::weak_ptr<Client::Impl>(impl), fn = std::move(fn)]() mutable {
    if (auto self = weak.lock(); self && !self->shut_down) {
      fn(*self);
    }
  });
}

}  // namespace

Client::Client(net::EventLoop& loop, ClientConfig config)
    : loop_(loop), impl_(std::make_shared<Impl>(loop, std::move(config))) {}

Client::~Client() {
  if (loop_.in_loop_thread()) {
    impl_->shutdown();
    return;
  }
  std::promise<void> finished;
  loop_.post([impl = impl_, &finished]() {
    impl->shutdown();
    finished.set_value();
  });
  finished.get_future().wait();
}

void Client::connect(std::function<void(Status)> done) {
  post_to(loop_, impl_, [done = std::move(done)](Impl& impl) mutable { impl.connect(std::move(done)); });
}

void Client::disconnect(std::function<void()> done) {
  post_to(loop_, impl_, [done = std::move(done)](Impl& impl) mutable { impl.disconnect(std::move(done)); });
}

void Client::set_on_state(std::function<void(ClientState, const Status&)> on_state) {
  post_to(loop_, impl_, [fn = std::move(on_state)](Impl& impl) mutable { impl.on_state = std::move(fn); });
}

void Client::read(std::vector<ReadValueId> nodes, std::function<void(Result<std::vector<DataValue>>)> done) {
  post_to(loop_, impl_, [nodes = std::move(nodes), done = std::move(done)](Impl& impl) mutable {
    impl.read(std::move(nodes), std::move(done));
  });
}

void Client::write(std::vector<WriteValue> nodes, std::function<void(Result<std::vector<StatusCode>>)> done) {
  post_to(loop_, impl_, [nodes = std::move(nodes), done = std::move(done)](Impl& impl) mutable {
    impl.write(std::move(nodes), std::move(done));
  });
}

void Client::browse(BrowseDescription node,
                    std::function<void(Result<std::vector<ReferenceDescription>>)> done) {
  post_to(loop_, impl_, [node = std::move(node), done = std::move(done)](Impl& impl) mutable {
    impl.browse(std::move(node), std::move(done));
  });
}

void Client::translate(std::vector<BrowsePath> paths,
                       std::function<void(Result<std::vector<BrowsePathResult>>)> done) {
  post_to(loop_, impl_, [paths = std::move(paths), done = std::move(done)](Impl& impl) mutable {
    impl.translate(std::move(paths), std::move(done));
  });
}

void Client::call(std::vector<CallMethodRequest> methods,
                  std::function<void(Result<std::vector<CallMethodResult>>)> done) {
  post_to(loop_, impl_, [methods = std::move(methods), done = std::move(done)](Impl& impl) mutable {
    impl.call(std::move(methods), std::move(done));
  });
}

void Client::history_read_raw(NodeId node, HistoryRawParams params,
                              std::function<void(Result<std::vector<DataValue>>)> done) {
  post_to(loop_, impl_, [node = std::move(node), params, done = std::move(done)](Impl& impl) mutable {
    impl.history_read_raw(std::move(node), params, {}, ByteString(), std::move(done));
  });
}

void Client::get_endpoints(std::function<void(Result<std::vector<EndpointDescription>>)> done) {
  post_to(loop_, impl_,
          [done = std::move(done)](Impl& impl) mutable { impl.get_endpoints(std::move(done)); });
}

void Client::find_servers(std::vector<std::string> server_uris,
                          std::function<void(Result<std::vector<ApplicationDescription>>)> done) {
  post_to(loop_, impl_, [uris = std::move(server_uris), done = std::move(done)](Impl& impl) mutable {
    impl.find_servers(std::move(uris), std::move(done));
  });
}

void Client::create_subscription(SubscriptionParams params,
                                 std::function<void(Result<SubscriptionId>)> done) {
  post_to(loop_, impl_, [params, done = std::move(done)](Impl& impl) mutable {
    impl.create_subscription(params, std::move(done));
  });
}

void Client::monitor_value(SubscriptionId subscription, ReadValueId item, MonitoringParameters parameters,
                           DataChangeCallback on_change, MonitorDone done) {
  Impl::MonitoredItem monitored;
  monitored.item = std::move(item);
  monitored.parameters = std::move(parameters);
  monitored.on_change = std::move(on_change);
  post_to(loop_, impl_,
          [subscription, monitored = std::move(monitored), done = std::move(done)](Impl& impl) mutable {
            impl.add_monitored_item(subscription, std::move(monitored), std::move(done));
          });
}

void Client::monitor_events(SubscriptionId subscription, NodeId notifier, EventFilter filter,
                            EventCallback on_event, MonitorDone done) {
  Impl::MonitoredItem monitored;
  monitored.item.node_id = std::move(notifier);
  monitored.item.attribute_id = attribute_id::EventNotifier;
  // Events are not sampled (OPC 10000-4 §5.12.1.2): interval 0; a queue so that bursts between
  // two publishing cycles survive.
  monitored.parameters.sampling_interval = 0;
  monitored.parameters.queue_size = 100;
  monitored.parameters.discard_oldest = true;
  monitored.parameters.filter = ExtensionObject::make(std::move(filter));
  monitored.on_event = std::move(on_event);
  post_to(loop_, impl_,
          [subscription, monitored = std::move(monitored), done = std::move(done)](Impl& impl) mutable {
            impl.add_monitored_item(subscription, std::move(monitored), std::move(done));
          });
}

void Client::unmonitor(SubscriptionId subscription, std::uint32_t client_handle,
                       std::function<void(Status)> done) {
  post_to(loop_, impl_, [subscription, client_handle, done = std::move(done)](Impl& impl) mutable {
    impl.unmonitor(subscription, client_handle, std::move(done));
  });
}

void Client::delete_subscription(SubscriptionId subscription, std::function<void(Status)> done) {
  post_to(loop_, impl_, [subscription, done = std::move(done)](Impl& impl) mutable {
    impl.delete_subscription(subscription, std::move(done));
  });
}

ClientState Client::state() const {
  return impl_->state_mirror.load();
}

BrowseDescription browse_children_of(const NodeId& node) {
  BrowseDescription description;
  description.node_id = node;
  description.browse_direction = BrowseDirection::Forward;
  description.reference_type_id = NodeId(0, id::HierarchicalReferences);
  description.include_subtypes = true;
  description.node_class_mask = 0;  // all node classes
  description.result_mask = static_cast<std::uint32_t>(BrowseResultMask::All);
  return description;
}

ReadValueId value_of(const NodeId& node) {
  ReadValueId read;
  read.node_id = node;
  read.attribute_id = attribute_id::Value;
  return read;
}

EventFilter select_event_fields(const std::vector<std::string>& base_event_fields) {
  EventFilter filter;
  for (const auto& name : base_event_fields) {
    SimpleAttributeOperand operand;
    operand.type_definition_id = NodeId(0, id::BaseEventType);
    // "A/B" names a property of a component (e.g. "EnabledState/Id").
    std::string_view rest = name;
    while (!rest.empty()) {
      const auto slash = rest.find('/');
      operand.browse_path.push_back(QualifiedName(0, String(rest.substr(0, slash))));
      rest = slash == std::string_view::npos ? std::string_view() : rest.substr(slash + 1);
    }
    operand.attribute_id = attribute_id::Value;
    filter.select_clauses.push_back(std::move(operand));
  }
  return filter;
}

}  // namespace sf::opcua
