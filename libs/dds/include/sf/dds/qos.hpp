// QoS: an owned dds_qos_t and a builder for the policies the shop floor uses
// (DDS 1.4 §2.2.3: RELIABILITY, DURABILITY, DEADLINE, LIVELINESS, HISTORY,
// PARTITION, ENTITY_NAME / USER_DATA, WRITER_DATA_LIFECYCLE). QosSettings reads a QoS back, so tests
// can check what an entity really got.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <dds/dds.h>

namespace sf::dds {

// Names follow the DDS specification's policy kinds.
enum class Reliability { BestEffort, Reliable };
enum class Durability { Volatile, TransientLocal };
enum class Liveliness { Automatic, ManualByParticipant, ManualByTopic };
enum class History { KeepLast, KeepAll };

// "Infinite" for deadline, lease and blocking time (DDS_INFINITY).
inline constexpr std::chrono::nanoseconds kInfinite = std::chrono::nanoseconds::max();

class Qos {
 public:
  Qos();
  ~Qos();
  Qos(const Qos& other);
  Qos& operator=(const Qos& other);
  Qos(Qos&& other) noexcept;
  Qos& operator=(Qos&& other) noexcept;

  [[nodiscard]] const dds_qos_t* get() const { return qos_; }
  [[nodiscard]] dds_qos_t* get() { return qos_; }
  // Takes ownership of a dds_qos_t (e.g. from dds_get_qos).
  static Qos adopt(dds_qos_t* qos);

 private:
  explicit Qos(dds_qos_t* qos) : qos_(qos) {}
  dds_qos_t* qos_;
};

// The policies a QoS sets; unset policies are nullopt (Cyclone's default applies).
struct QosSettings {
  std::optional<Reliability> reliability;
  std::optional<std::chrono::nanoseconds> max_blocking_time;
  std::optional<Durability> durability;
  std::optional<std::chrono::nanoseconds> deadline;
  std::optional<Liveliness> liveliness;
  std::optional<std::chrono::nanoseconds> lease_duration;
  std::optional<History> history;
  std::optional<std::int32_t> history_depth;
  std::optional<std::vector<std::string>> partitions;
  std::optional<std::string> entity_name;
  std::optional<std::string> user_data;
  std::optional<bool> autodispose_unregistered_instances;
};

// Reads the policies of a QoS back.
QosSettings read_settings(const Qos& qos);

class QosBuilder {
 public:
  // RELIABLE: a writer blocks up to max_blocking when the reader's history is full.
  QosBuilder& reliable(std::chrono::nanoseconds max_blocking = std::chrono::milliseconds{100});
  QosBuilder& best_effort();
  QosBuilder& durability(Durability kind);
  // DEADLINE: the period within which each instance must be updated.
  QosBuilder& deadline(std::chrono::nanoseconds period);
  // LIVELINESS: a writer not asserted within `lease` is reported not alive.
  QosBuilder& liveliness(Liveliness kind, std::chrono::nanoseconds lease);
  QosBuilder& keep_last(std::int32_t depth);
  QosBuilder& keep_all();
  // PARTITION (publisher/subscriber only): endpoints match only within a partition.
  QosBuilder& partition(std::string name);
  QosBuilder& entity_name(std::string name);
  QosBuilder& user_data(std::string data);
  // WRITER_DATA_LIFECYCLE (DDS 1.4 §2.2.3.21; default true): unregistering an
  // instance also disposes it, in the same message.
  QosBuilder& autodispose_unregistered_instances(bool on);

  [[nodiscard]] Qos build() const;
  [[nodiscard]] const QosSettings& settings() const { return s_; }

 private:
  QosSettings s_;
};

}  // namespace sf::dds
