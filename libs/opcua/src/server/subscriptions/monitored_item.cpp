// Monitored item queues and samples (OPC 10000-4 §5.12.1.4, §5.12.1.5).
#include <chrono>
#include <functional>
#include <utility>

#include "server/subscriptions/engine.hpp"

namespace sf::opcua::subs {
namespace {

void set_overflow(DataValue& value) {
  value.status = StatusCode(value.status.value() | kOverflowInfoBits);
}

bool has_overflow_marker(const MonitoredItem& item) {
  for (const auto& e : item.events) {
    if (e.overflow_marker) {
      return true;
    }
  }
  return false;
}

}  // namespace

Clock::duration milliseconds(double ms) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

void enqueue_value(MonitoredItem& item, DataValue value) {
  auto& q = item.values;
  if (q.size() < item.queue_size) {
    q.push_back(std::move(value));
    return;
  }
  if (item.queue_size <= 1) {
    // "The discard policy is ignored if the queue size is one": the newest value wins.
    q.clear();
    q.push_back(std::move(value));
    return;
  }
  if (item.discard_oldest) {
    q.pop_front();
    q.push_back(std::move(value));
    set_overflow(q.front());
  } else {
    q.back() = std::move(value);
    set_overflow(q.back());
  }
}

void enqueue_event(MonitoredItem& item, Array<Variant> fields,
                   const std::function<Array<Variant>()>& overflow_event) {
  auto& q = item.events;
  // The overflow marker is "in addition to the size of the queue" (§5.12.1.5).
  const std::size_t used = q.size() - (has_overflow_marker(item) ? 1U : 0U);
  if (used < item.queue_size) {
    q.push_back({std::move(fields), false});
    return;
  }
  const bool first_loss = !has_overflow_marker(item);
  if (item.discard_oldest) {
    // The marker sits at the front and is never discarded.
    q.erase(q.begin() + (q.front().overflow_marker ? 1 : 0));
    q.push_back({std::move(fields), false});
    if (first_loss) {
      q.push_front({overflow_event(), true});
    }
  } else {
    if (q.back().overflow_marker) {
      q.erase(q.end() - 2);
      q.insert(q.end() - 1, {std::move(fields), false});
    } else {
      q.back() = {std::move(fields), false};
    }
    if (first_loss) {
      q.push_back({overflow_event(), true});
    }
  }
}

DataValue apply_timestamps(DataValue value, TimestampsToReturn timestamps, DateTime now) {
  const bool source = timestamps == TimestampsToReturn::Source || timestamps == TimestampsToReturn::Both;
  const bool server = timestamps == TimestampsToReturn::Server || timestamps == TimestampsToReturn::Both;
  if (!source) {
    value.source_timestamp = DateTime{};
    value.source_picoseconds = 0;
  }
  if (!server) {
    value.server_timestamp = DateTime{};
    value.server_picoseconds = 0;
  } else if (value.server_timestamp.is_min()) {
    value.server_timestamp = now;
  }
  return value;
}

void offer_sample(MonitoredItem& item, const DataValue& sample, DateTime now) {
  if (item.last && !is_reportable_change(item.data_filter, *item.last, sample)) {
    return;
  }
  item.last = sample;
  enqueue_value(item, apply_timestamps(sample, item.timestamps, now));
}

}  // namespace sf::opcua::subs
