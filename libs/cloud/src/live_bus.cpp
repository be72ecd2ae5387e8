#include "sf/cloud/live_bus.hpp"

#include <vector>

namespace sf::cloud {

LiveBus::Subscription& LiveBus::Subscription::operator=(Subscription&& other) noexcept {
  if (this != &other) {
    if (bus_ != nullptr) {
      bus_->unsubscribe(id_);
    }
    bus_ = other.bus_;
    id_ = other.id_;
    other.bus_ = nullptr;
  }
  return *this;
}

LiveBus::Subscription::~Subscription() {
  if (bus_ != nullptr) {
    bus_->unsubscribe(id_);
  }
}

LiveBus::Subscription LiveBus::subscribe(Callback on_value, EventCallback on_event) {
  std::lock_guard lock(mutex_);
  const std::size_t id = next_++;
  entries_[id] = std::make_shared<Entry>(Entry{std::move(on_value), std::move(on_event)});
  return {this, id};
}

LiveBus::Subscription LiveBus::subscribe_with_current(const Callback& on_value, EventCallback on_event) {
  std::vector<Retained> current;
  Subscription subscription;
  {
    std::lock_guard lock(mutex_);
    current.reserve(retained_.size());
    for (const auto& [key, r] : retained_) {
      current.push_back(r);
    }
    const std::size_t id = next_++;
    entries_[id] = std::make_shared<Entry>(Entry{on_value, std::move(on_event)});
    subscription = Subscription(this, id);
  }
  for (const auto& r : current) {
    on_value(LiveUpdate{&r.series, r.sample, true});
  }
  return subscription;
}

void LiveBus::unsubscribe(std::size_t id) {
  std::lock_guard lock(mutex_);
  entries_.erase(id);
}

std::size_t LiveBus::subscribers() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

// The callbacks run outside the lock on a snapshot, so a subscriber may come or go meanwhile.
std::vector<std::shared_ptr<LiveBus::Entry>> LiveBus::snapshot() const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<Entry>> out;
  out.reserve(entries_.size());
  for (const auto& [id, entry] : entries_) {
    out.push_back(entry);
  }
  return out;
}

void LiveBus::publish(const LiveUpdate& update) {
  if (update.series != nullptr) {
    std::lock_guard lock(mutex_);
    auto [it, added] = retained_.try_emplace({update.series->server, update.series->node_id});
    if (added || update.sample.source_time >= it->second.sample.source_time) {
      it->second = {*update.series, update.sample};
    }
  }
  for (const auto& entry : snapshot()) {
    if (entry->on_value) {
      entry->on_value(update);
    }
  }
}

void LiveBus::publish(const historian::Event& event) {
  for (const auto& entry : snapshot()) {
    if (entry->on_event) {
      entry->on_event(event);
    }
  }
}

}  // namespace sf::cloud
