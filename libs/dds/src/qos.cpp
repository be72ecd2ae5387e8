#include "sf/dds/qos.hpp"

#include <cstring>
#include <utility>

namespace sf::dds {
namespace {

dds_duration_t to_dds(std::chrono::nanoseconds d) {
  return d == kInfinite ? DDS_INFINITY : static_cast<dds_duration_t>(d.count());
}

std::chrono::nanoseconds from_dds(dds_duration_t d) {
  return d == DDS_INFINITY ? kInfinite : std::chrono::nanoseconds{d};
}

void read_reliability(const dds_qos_t* q, QosSettings& s) {
  dds_reliability_kind_t kind{};
  dds_duration_t blocking = 0;
  if (dds_qget_reliability(q, &kind, &blocking)) {
    s.reliability = kind == DDS_RELIABILITY_RELIABLE ? Reliability::Reliable : Reliability::BestEffort;
    s.max_blocking_time = from_dds(blocking);
  }
}

void read_durability_history(const dds_qos_t* q, QosSettings& s) {
  dds_durability_kind_t dur{};
  if (dds_qget_durability(q, &dur)) {
    s.durability = dur == DDS_DURABILITY_VOLATILE ? Durability::Volatile : Durability::TransientLocal;
  }
  dds_history_kind_t hist{};
  std::int32_t depth = 0;
  if (dds_qget_history(q, &hist, &depth)) {
    s.history = hist == DDS_HISTORY_KEEP_ALL ? History::KeepAll : History::KeepLast;
    s.history_depth = depth;
  }
}

void read_timing(const dds_qos_t* q, QosSettings& s) {
  dds_duration_t period = 0;
  if (dds_qget_deadline(q, &period)) {
    s.deadline = from_dds(period);
  }
  dds_liveliness_kind_t kind{};
  dds_duration_t lease = 0;
  if (dds_qget_liveliness(q, &kind, &lease)) {
    s.liveliness = kind == DDS_LIVELINESS_AUTOMATIC               ? Liveliness::Automatic
                   : kind == DDS_LIVELINESS_MANUAL_BY_PARTICIPANT ? Liveliness::ManualByParticipant
                                                                  : Liveliness::ManualByTopic;
    s.lease_duration = from_dds(lease);
  }
}

void read_names(const dds_qos_t* q, QosSettings& s) {
  std::uint32_t n = 0;
  char** names = nullptr;
  if (dds_qget_partition(q, &n, &names)) {
    std::vector<std::string> parts;
    for (std::uint32_t i = 0; i < n; ++i) {
      parts.emplace_back(names[i]);
      dds_free(names[i]);
    }
    dds_free(static_cast<void*>(names));
    s.partitions = std::move(parts);
  }
  char* name = nullptr;
  if (dds_qget_entity_name(q, &name) && name != nullptr) {
    s.entity_name = std::string{name};
    dds_free(name);
  }
  void* data = nullptr;
  std::size_t size = 0;
  if (dds_qget_userdata(q, &data, &size)) {
    s.user_data = std::string(static_cast<const char*>(data), size);
    dds_free(data);
  }
}

}  // namespace

Qos::Qos() : qos_(dds_create_qos()) {}
Qos::~Qos() {
  if (qos_ != nullptr) {
    dds_delete_qos(qos_);
  }
}
Qos::Qos(const Qos& other) : qos_(dds_create_qos()) {
  dds_copy_qos(qos_, other.qos_);
}
Qos& Qos::operator=(const Qos& other) {
  if (this != &other) {
    dds_reset_qos(qos_);
    dds_copy_qos(qos_, other.qos_);
  }
  return *this;
}
Qos::Qos(Qos&& other) noexcept : qos_(std::exchange(other.qos_, dds_create_qos())) {}
Qos& Qos::operator=(Qos&& other) noexcept {
  std::swap(qos_, other.qos_);
  return *this;
}
Qos Qos::adopt(dds_qos_t* qos) {
  return Qos{qos};
}

QosSettings read_settings(const Qos& qos) {
  QosSettings s;
  read_reliability(qos.get(), s);
  read_durability_history(qos.get(), s);
  read_timing(qos.get(), s);
  read_names(qos.get(), s);
  bool autodispose = true;
  if (dds_qget_writer_data_lifecycle(qos.get(), &autodispose)) {
    s.autodispose_unregistered_instances = autodispose;
  }
  return s;
}

QosBuilder& QosBuilder::reliable(std::chrono::nanoseconds max_blocking) {
  s_.reliability = Reliability::Reliable;
  s_.max_blocking_time = max_blocking;
  return *this;
}
QosBuilder& QosBuilder::best_effort() {
  s_.reliability = Reliability::BestEffort;
  s_.max_blocking_time = std::chrono::nanoseconds{0};
  return *this;
}
QosBuilder& QosBuilder::durability(Durability kind) {
  s_.durability = kind;
  return *this;
}
QosBuilder& QosBuilder::deadline(std::chrono::nanoseconds period) {
  s_.deadline = period;
  return *this;
}
QosBuilder& QosBuilder::liveliness(Liveliness kind, std::chrono::nanoseconds lease) {
  s_.liveliness = kind;
  s_.lease_duration = lease;
  return *this;
}
QosBuilder& QosBuilder::keep_last(std::int32_t depth) {
  s_.history = History::KeepLast;
  s_.history_depth = depth;
  return *this;
}
QosBuilder& QosBuilder::keep_all() {
  s_.history = History::KeepAll;
  s_.history_depth = -1;
  return *this;
}
QosBuilder& QosBuilder::partition(std::string name) {
  if (!s_.partitions) {
    s_.partitions.emplace();
  }
  s_.partitions->push_back(std::move(name));
  return *this;
}
QosBuilder& QosBuilder::entity_name(std::string name) {
  s_.entity_name = std::move(name);
  return *this;
}
QosBuilder& QosBuilder::user_data(std::string data) {
  s_.user_data = std::move(data);
  return *this;
}

QosBuilder& QosBuilder::autodispose_unregistered_instances(bool on) {
  s_.autodispose_unregistered_instances = on;
  return *this;
}

Qos QosBuilder::build() const {
  Qos qos;
  dds_qos_t* q = qos.get();
  if (s_.reliability) {
    dds_qset_reliability(
        q, *s_.reliability == Reliability::Reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
        to_dds(s_.max_blocking_time.value_or(std::chrono::milliseconds{100})));
  }
  if (s_.durability) {
    dds_qset_durability(
        q, *s_.durability == Durability::Volatile ? DDS_DURABILITY_VOLATILE : DDS_DURABILITY_TRANSIENT_LOCAL);
  }
  if (s_.deadline) {
    dds_qset_deadline(q, to_dds(*s_.deadline));
  }
  if (s_.liveliness) {
    const auto kind = *s_.liveliness == Liveliness::Automatic ? DDS_LIVELINESS_AUTOMATIC
                      : *s_.liveliness == Liveliness::ManualByParticipant
                          ? DDS_LIVELINESS_MANUAL_BY_PARTICIPANT
                          : DDS_LIVELINESS_MANUAL_BY_TOPIC;
    dds_qset_liveliness(q, kind, to_dds(s_.lease_duration.value_or(kInfinite)));
  }
  if (s_.history) {
    dds_qset_history(q, *s_.history == History::KeepAll ? DDS_HISTORY_KEEP_ALL : DDS_HISTORY_KEEP_LAST,
                     s_.history_depth.value_or(1));
  }
  if (s_.partitions) {
    std::vector<const char*> names;
    for (const auto& p : *s_.partitions) {
      names.push_back(p.c_str());
    }
    dds_qset_partition(q, static_cast<std::uint32_t>(names.size()), names.data());
  }
  if (s_.entity_name) {
    dds_qset_entity_name(q, s_.entity_name->c_str());
  }
  if (s_.user_data) {
    dds_qset_userdata(q, s_.user_data->data(), s_.user_data->size());
  }
  if (s_.autodispose_unregistered_instances) {
    dds_qset_writer_data_lifecycle(q, *s_.autodispose_unregistered_instances);
  }
  return qos;
}

}  // namespace sf::dds
