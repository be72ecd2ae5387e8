// Sample metadata and communication statuses (DDS 1.4 §2.2.4.1) as plain
// values that can be posted to the application's executor.
#pragma once

#include <cstdint>

#include <dds/dds.h>

namespace sf::dds {

// DDS 1.4 §2.2.2.5.1.x instance states.
enum class InstanceState { Alive, Disposed, NoWriters };

struct SampleInfo {
  bool valid_data = false;  // false: only the key fields are meaningful (dispose/unregister)
  InstanceState instance_state = InstanceState::Alive;
  dds_instance_handle_t instance_handle = 0;
  dds_instance_handle_t publication_handle = 0;  // the writer that wrote it
  std::int64_t source_timestamp_ns = 0;          // writer's clock, ns since the UTC epoch
};

// SUBSCRIPTION_MATCHED / PUBLICATION_MATCHED.
struct MatchedStatus {
  std::uint32_t total_count = 0;
  std::uint32_t current_count = 0;
  std::int32_t current_count_change = 0;
  dds_instance_handle_t last_handle = 0;  // the remote endpoint that (un)matched
};

// LIVELINESS_CHANGED: a matched writer became alive or not alive (or went away).
struct LivelinessChangedStatus {
  std::uint32_t alive_count = 0;
  std::uint32_t not_alive_count = 0;
  std::int32_t alive_count_change = 0;
  std::int32_t not_alive_count_change = 0;
  dds_instance_handle_t last_publication_handle = 0;
};

// REQUESTED_DEADLINE_MISSED / OFFERED_DEADLINE_MISSED.
struct DeadlineMissedStatus {
  std::uint32_t total_count = 0;
  std::int32_t total_count_change = 0;
  dds_instance_handle_t last_instance_handle = 0;
};

// LIVELINESS_LOST (writer): this writer failed to assert its liveliness.
struct LivelinessLostStatus {
  std::uint32_t total_count = 0;
  std::int32_t total_count_change = 0;
};

}  // namespace sf::dds
