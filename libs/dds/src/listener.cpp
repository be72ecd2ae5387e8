#include "sf/dds/listener.hpp"

#include <utility>

namespace sf::dds::detail {
namespace {

ListenerCore* core_of(void* arg) {
  return static_cast<ListenerCore*>(arg);
}

void on_data_available(dds_entity_t /*reader*/, void* arg) {
  core_of(arg)->post_data_available();
}

void on_subscription_matched(dds_entity_t /*reader*/, const dds_subscription_matched_status_t s, void* arg) {
  auto* core = core_of(arg);
  const MatchedStatus st{s.total_count, s.current_count, s.current_count_change, s.last_publication_handle};
  core->post([core, st] {
    if (core->reader.on_subscription_matched) {
      core->reader.on_subscription_matched(st);
    }
  });
}

void on_liveliness_changed(dds_entity_t /*reader*/, const dds_liveliness_changed_status_t s, void* arg) {
  auto* core = core_of(arg);
  const LivelinessChangedStatus st{s.alive_count, s.not_alive_count, s.alive_count_change,
                                   s.not_alive_count_change, s.last_publication_handle};
  core->post([core, st] {
    if (core->reader.on_liveliness_changed) {
      core->reader.on_liveliness_changed(st);
    }
  });
}

void on_requested_deadline_missed(dds_entity_t /*reader*/, const dds_requested_deadline_missed_status_t s,
                                  void* arg) {
  auto* core = core_of(arg);
  const DeadlineMissedStatus st{s.total_count, s.total_count_change, s.last_instance_handle};
  core->post([core, st] {
    if (core->reader.on_requested_deadline_missed) {
      core->reader.on_requested_deadline_missed(st);
    }
  });
}

void on_publication_matched(dds_entity_t /*writer*/, const dds_publication_matched_status_t s, void* arg) {
  auto* core = core_of(arg);
  const MatchedStatus st{s.total_count, s.current_count, s.current_count_change, s.last_subscription_handle};
  core->post([core, st] {
    if (core->writer.on_publication_matched) {
      core->writer.on_publication_matched(st);
    }
  });
}

void on_liveliness_lost(dds_entity_t /*writer*/, const dds_liveliness_lost_status_t s, void* arg) {
  auto* core = core_of(arg);
  const LivelinessLostStatus st{s.total_count, s.total_count_change};
  core->post([core, st] {
    if (core->writer.on_liveliness_lost) {
      core->writer.on_liveliness_lost(st);
    }
  });
}

void on_offered_deadline_missed(dds_entity_t /*writer*/, const dds_offered_deadline_missed_status_t s,
                                void* arg) {
  auto* core = core_of(arg);
  const DeadlineMissedStatus st{s.total_count, s.total_count_change, s.last_instance_handle};
  core->post([core, st] {
    if (core->writer.on_offered_deadline_missed) {
      core->writer.on_offered_deadline_missed(st);
    }
  });
}

}  // namespace

void ListenerCore::post(std::function<void()> fn) {
  // The task shares ownership of the core, so it can run (as a no-op) even
  // after the endpoint that owned the core is gone.
  executor_->post([self = shared_from_this(), fn = std::move(fn)] {
    const std::lock_guard lock{self->mutex_};
    if (!self->closed_) {
      fn();
    }
  });
}

void ListenerCore::post_data_available() {
  if (data_pending_.exchange(true)) {
    return;  // a take-all task is already queued
  }
  post([this] {
    // Cleared before taking, so data arriving during the take queues a new task.
    data_pending_.store(false);
    const dds_entity_t e = entity.load();
    if (on_data && e > 0) {
      on_data(e);
    }
  });
}

void ListenerCore::close() {
  const std::lock_guard lock{mutex_};
  closed_ = true;
}

dds_listener_t* make_reader_listener(ListenerCore* core) {
  if (core == nullptr) {
    return nullptr;
  }
  dds_listener_t* l = dds_create_listener(core);
  if (core->on_data) {
    dds_lset_data_available(l, on_data_available);
  }
  if (core->reader.on_subscription_matched) {
    dds_lset_subscription_matched(l, on_subscription_matched);
  }
  if (core->reader.on_liveliness_changed) {
    dds_lset_liveliness_changed(l, on_liveliness_changed);
  }
  if (core->reader.on_requested_deadline_missed) {
    dds_lset_requested_deadline_missed(l, on_requested_deadline_missed);
  }
  return l;
}

dds_listener_t* make_writer_listener(ListenerCore* core) {
  if (core == nullptr) {
    return nullptr;
  }
  dds_listener_t* l = dds_create_listener(core);
  if (core->writer.on_publication_matched) {
    dds_lset_publication_matched(l, on_publication_matched);
  }
  if (core->writer.on_liveliness_lost) {
    dds_lset_liveliness_lost(l, on_liveliness_lost);
  }
  if (core->writer.on_offered_deadline_missed) {
    dds_lset_offered_deadline_missed(l, on_offered_deadline_missed);
  }
  return l;
}

}  // namespace sf::dds::detail
