// Test fixture for the subscriptions engine: a fake address space behind the callbacks, a
// ManualClock driven like the server's timer, and helpers to read Publish responses.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/opcua/node_ids.hpp"
#include "sf/opcua/server/subscriptions.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::subs_test {

inline constexpr std::uint32_t kValue = 13;
inline constexpr std::uint32_t kEventNotifier = 12;
inline constexpr std::uint32_t kBrowseName = 3;
inline constexpr std::uint32_t kOverflow = 0x0480;

struct FakeNode {
  DataValue value;
  bool is_object = false;
  bool notifier = false;
  std::optional<Range> eu_range;
};

inline NodeId node(const char* name) {
  return NodeId(1, String(name));
}

// What one Publish request got back.
struct Answer {
  std::uint32_t handle = 0;
  Message message;
};

class SubscriptionsTest : public ::testing::Test {
 protected:
  SubscriptionsTest() {
    nodes[NodeId(0, id::Server)] = FakeNode{{}, true, true, {}};
    make();
  }

  void make(SubscriptionLimits limits = {}) {
    SubscriptionCallbacks cb;
    cb.read = [this](const ReadValueId& r, TimestampsToReturn ts) { return read(r, ts); };
    cb.eu_range = [this](const NodeId& n) -> std::optional<Range> {
      auto it = nodes.find(n);
      return it == nodes.end() ? std::nullopt : it->second.eu_range;
    };
    cb.is_event_notifier = [this](const NodeId& n) {
      auto it = nodes.find(n);
      return it != nodes.end() && it->second.notifier;
    };
    cb.is_subtype = [this](const NodeId& type, const NodeId& base) {
      for (NodeId t = type;;) {
        if (t == base) {
          return true;
        }
        auto it = parent_type.find(t);
        if (it == parent_type.end()) {
          return false;
        }
        t = it->second;
      }
    };
    svc = std::make_unique<SubscriptionService>(clock, limits, std::move(cb));
  }

  DataValue read(const ReadValueId& r, TimestampsToReturn /*ts*/) {
    ++reads;
    DataValue dv;
    auto it = nodes.find(r.node_id);
    if (it == nodes.end()) {
      dv.status = status::BadNodeIdUnknown;
      return dv;
    }
    const FakeNode& n = it->second;
    if (r.attribute_id == kValue && !n.is_object) {
      dv = n.value;
      dv.server_timestamp = DateTime::from_system_clock(clock.utc_now());
    } else if (r.attribute_id == kEventNotifier && n.is_object) {
      dv.value = Variant(static_cast<std::uint8_t>(n.notifier ? 1 : 0));
    } else if (r.attribute_id == kBrowseName) {
      dv.value = Variant(QualifiedName(1, "name"));
    } else {
      dv.status = status::BadAttributeIdInvalid;
    }
    return dv;
  }

  // A variable with a value; its source timestamp stays the same unless given.
  void set(const NodeId& n, Variant v, StatusCode st = {},
           DateTime source = DateTime(130'000'000'000'000'000)) {
    auto& fake = nodes[n];
    fake.value.value = std::move(v);
    fake.value.status = st;
    fake.value.source_timestamp = source;
  }

  // Moves time forward as the server's timer would: tick() at every next_due() on the way.
  void advance(int ms) {
    const auto target = clock.now() + std::chrono::milliseconds(ms);
    for (int guard = 0; guard < 100'000; ++guard) {
      const auto due = svc->next_due();
      if (due > target) {
        break;
      }
      clock.set(std::max(due, clock.now()));
      svc->tick();
    }
    clock.set(target);
    svc->tick();
  }

  RequestHeader header(std::uint32_t handle = 0, std::uint32_t timeout_hint = 0) {
    RequestHeader h;
    h.request_handle = handle;
    h.timeout_hint = timeout_hint;
    return h;
  }

  std::uint32_t create_sub(double interval = 100, std::uint32_t keep_alive = 3, std::uint32_t lifetime = 30,
                           std::uint32_t max_notifications = 0, bool enabled = true,
                           const SessionKey& s = session()) {
    CreateSubscriptionRequest req;
    req.request_header = header();
    req.requested_publishing_interval = interval;
    req.requested_max_keep_alive_count = keep_alive;
    req.requested_lifetime_count = lifetime;
    req.max_notifications_per_publish = max_notifications;
    req.publishing_enabled = enabled;
    auto resp = svc->create_subscription(s, req);
    EXPECT_EQ(resp.response_header.service_result, status::Good);
    return resp.subscription_id;
  }

  static MonitoringParameters params(std::uint32_t handle, double sampling = -1, std::uint32_t queue = 1,
                                     bool discard_oldest = true, ExtensionObject filter = {}) {
    MonitoringParameters p;
    p.client_handle = handle;
    p.sampling_interval = sampling;
    p.queue_size = queue;
    p.discard_oldest = discard_oldest;
    p.filter = std::move(filter);
    return p;
  }

  static MonitoredItemCreateRequest item_request(const NodeId& n, MonitoringParameters p,
                                                 MonitoringMode mode = MonitoringMode::Reporting,
                                                 std::uint32_t attribute = kValue) {
    MonitoredItemCreateRequest r;
    r.item_to_monitor.node_id = n;
    r.item_to_monitor.attribute_id = attribute;
    r.monitoring_mode = mode;
    r.requested_parameters = std::move(p);
    return r;
  }

  CreateMonitoredItemsResponse create_items(std::uint32_t sub, std::vector<MonitoredItemCreateRequest> items,
                                            TimestampsToReturn ts = TimestampsToReturn::Both,
                                            const SessionKey& s = session()) {
    CreateMonitoredItemsRequest req;
    req.request_header = header();
    req.subscription_id = sub;
    req.timestamps_to_return = ts;
    req.items_to_create = std::move(items);
    return svc->create_monitored_items(s, req);
  }

  // Creates one item and expects it to succeed; returns its result.
  MonitoredItemCreateResult create_item(std::uint32_t sub, MonitoredItemCreateRequest item,
                                        TimestampsToReturn ts = TimestampsToReturn::Both) {
    auto resp = create_items(sub, {std::move(item)}, ts);
    EXPECT_EQ(resp.response_header.service_result, status::Good);
    EXPECT_EQ(resp.results.size(), 1U);
    EXPECT_EQ(resp.results.at(0).status_code, status::Good) << to_string(resp.results.at(0).status_code);
    return resp.results.at(0);
  }

  void publish(std::uint32_t handle, std::vector<SubscriptionAcknowledgement> acks = {},
               std::uint32_t timeout_hint = 0, const SessionKey& s = session()) {
    PublishRequest req;
    req.request_header = header(handle, timeout_hint);
    req.subscription_acknowledgements = std::move(acks);
    svc->publish(s, req, [this, handle](Message m) { answers.push_back({handle, std::move(m)}); });
  }

  static SessionKey session() { return NodeId(0, String("session-A")); }
  static SessionKey other_session() { return NodeId(0, String("session-B")); }

  // The i-th answer as a PublishResponse (fails the test when it is a fault).
  const PublishResponse& response(std::size_t i) {
    static const PublishResponse none;
    if (i >= answers.size()) {
      ADD_FAILURE() << "no answer " << i << " (have " << answers.size() << ")";
      return none;
    }
    const auto* r = std::get_if<PublishResponse>(&answers[i].message);
    if (r == nullptr) {
      ADD_FAILURE() << "answer " << i << " is a fault: " << to_string(fault(i));
      return none;
    }
    return *r;
  }

  StatusCode fault(std::size_t i) {
    if (i >= answers.size()) {
      ADD_FAILURE() << "no answer " << i;
      return {};
    }
    const auto* f = std::get_if<ServiceFault>(&answers[i].message);
    return f == nullptr ? StatusCode{} : f->response_header.service_result;
  }

 public:
  static std::vector<MonitoredItemNotification> data(const PublishResponse& r) {
    std::vector<MonitoredItemNotification> out;
    for (const auto& eo : r.notification_message.notification_data) {
      if (const auto* d = eo.get_if<DataChangeNotification>()) {
        out.insert(out.end(), d->monitored_items.begin(), d->monitored_items.end());
      }
    }
    return out;
  }

  // (clientHandle, Double value) of each data notification.
  static std::vector<std::pair<std::uint32_t, double>> doubles(const PublishResponse& r) {
    std::vector<std::pair<std::uint32_t, double>> out;
    for (const auto& n : data(r)) {
      const auto* d = n.value.value.get_if<double>();
      out.emplace_back(n.client_handle, d != nullptr ? *d : -1e300);
    }
    return out;
  }

  static std::vector<EventFieldList> events(const PublishResponse& r) {
    std::vector<EventFieldList> out;
    for (const auto& eo : r.notification_message.notification_data) {
      if (const auto* e = eo.get_if<EventNotificationList>()) {
        out.insert(out.end(), e->events.begin(), e->events.end());
      }
    }
    return out;
  }

  static bool is_keep_alive(const PublishResponse& r) {
    return r.notification_message.notification_data.empty();
  }

 protected:
  ManualClock clock;
  std::unordered_map<NodeId, FakeNode> nodes;
  std::unordered_map<NodeId, NodeId> parent_type;
  std::unique_ptr<SubscriptionService> svc;
  std::vector<Answer> answers;
  int reads = 0;
};

using Pairs = std::vector<std::pair<std::uint32_t, double>>;

}  // namespace sf::opcua::subs_test
