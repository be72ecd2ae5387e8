// Listener plumbing shared by Reader<T> and Writer<T>: Cyclone's listener
// callbacks (on Cyclone's threads) post work to the application's Executor;
// the work runs there unless the endpoint was destroyed in the meantime.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>

#include <dds/dds.h>

#include "sf/dds/executor.hpp"
#include "sf/dds/status.hpp"

namespace sf::dds {

struct ReaderListeners {
  std::function<void(const MatchedStatus&)> on_subscription_matched;
  std::function<void(const LivelinessChangedStatus&)> on_liveliness_changed;
  std::function<void(const DeadlineMissedStatus&)> on_requested_deadline_missed;
};

struct WriterListeners {
  std::function<void(const MatchedStatus&)> on_publication_matched;
  std::function<void(const LivelinessLostStatus&)> on_liveliness_lost;
  std::function<void(const DeadlineMissedStatus&)> on_offered_deadline_missed;
};

namespace detail {

// Shared by the Cyclone listener (as its argument) and by the tasks it posts.
// close() makes every later task a no-op and waits for a running one, so no
// application callback runs after its endpoint is gone.
class ListenerCore : public std::enable_shared_from_this<ListenerCore> {
 public:
  explicit ListenerCore(Executor& executor) : executor_(&executor) {}

  // Posts fn to run on the executor while the core is open.
  void post(std::function<void()> fn);
  // Data arrivals are coalesced: one take-all task is queued at a time.
  void post_data_available();
  void close();

  // Set before the Cyclone listener is installed; gets the reader's handle.
  std::function<void(dds_entity_t)> on_data;
  std::atomic<dds_entity_t> entity{0};  // the endpoint, once created
  ReaderListeners reader;
  WriterListeners writer;

 private:
  Executor* executor_;
  std::recursive_mutex mutex_;  // recursive: an endpoint may be destroyed from its own callback
  bool closed_ = false;
  std::atomic<bool> data_pending_{false};
};

// A Cyclone listener whose callbacks forward to core (nullptr: no listener).
dds_listener_t* make_reader_listener(ListenerCore* core);
dds_listener_t* make_writer_listener(ListenerCore* core);

}  // namespace detail
}  // namespace sf::dds
