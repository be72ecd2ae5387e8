// Live updates inside the cloud process (paper Fig. 6: real-time data to applications): every
// value and event the gateway receives, fanned out to in-process subscribers such as the reasoner
// and the dashboard, before and independent of the database write.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "sf/historian/types.hpp"

namespace sf::cloud {

struct LiveUpdate {
  const historian::SeriesInfo* series = nullptr;  // valid during the callback
  historian::Sample sample;
  // Read back from the server's history after a (re)connect (ServerLink::catch_up): it may be
  // older than values of the series already delivered. Subscribers that keep a current value
  // skip these; those that keep every value (the knowledge loop's inspections) take them.
  bool replayed = false;
};

class LiveBus {
 public:
  using Callback = std::function<void(const LiveUpdate&)>;
  using EventCallback = std::function<void(const historian::Event&)>;

  // Unsubscribes when destroyed.
  class Subscription {
   public:
    Subscription() = default;
    Subscription(LiveBus* bus, std::size_t id) : bus_(bus), id_(id) {}
    Subscription(Subscription&& other) noexcept { *this = std::move(other); }
    Subscription& operator=(Subscription&& other) noexcept;
    Subscription(const Subscription&) = delete;
    Subscription& operator=(const Subscription&) = delete;
    ~Subscription();

   private:
    LiveBus* bus_ = nullptr;
    std::size_t id_ = 0;
  };

  // Callbacks run on the gateway's threads, one update at a time per server but those of different
  // servers at the same time (a thread per server): a subscriber guards its own state. Keep them
  // short. They may publish (callbacks run outside the bus's lock, as the knowledge loop's alarms
  // do) but never subscribe or unsubscribe.
  [[nodiscard]] Subscription subscribe(Callback on_value, EventCallback on_event = nullptr);
  // The same, and first the newest value of every series the bus has carried (as `replayed`
  // updates, on the calling thread): a subscriber that keeps current values starts with them
  // instead of waiting for each to change (retained values, as a broker keeps them). Live
  // updates may already come meanwhile; a replayed one may then be older.
  [[nodiscard]] Subscription subscribe_with_current(const Callback& on_value,
                                                    EventCallback on_event = nullptr);
  void publish(const LiveUpdate& update);
  void publish(const historian::Event& event);
  [[nodiscard]] std::size_t subscribers() const;

 private:
  void unsubscribe(std::size_t id);
  struct Entry {
    Callback on_value;
    EventCallback on_event;
  };
  [[nodiscard]] std::vector<std::shared_ptr<Entry>> snapshot() const;

  struct Retained {
    historian::SeriesInfo series;
    historian::Sample sample;
  };

  mutable std::mutex mutex_;
  std::map<std::size_t, std::shared_ptr<Entry>> entries_;
  std::map<std::pair<std::string, std::string>, Retained> retained_;  // (server, node id) → newest
  std::size_t next_ = 1;
};

}  // namespace sf::cloud
