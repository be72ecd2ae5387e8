// Topic<T>: a named, typed topic over an idlc-generated C type. The type's
// descriptor is found through TopicType<T>, declared next to the generated
// header with SF_DDS_TOPIC_TYPE(sf_cnp_Announce).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <dds/dds.h>
#include <fmt/format.h>

#include "sf/core/result.hpp"
#include "sf/dds/entity.hpp"
#include "sf/dds/participant.hpp"
#include "sf/dds/qos.hpp"

namespace sf::dds {

template <typename T>
struct TopicType;  // static const dds_topic_descriptor_t& descriptor();

template <typename T>
class Topic {
 public:
  static Result<Topic> create(const Participant& participant, std::string name, const Qos* qos = nullptr) {
    const dds_entity_t t = dds_create_topic(participant.handle(), &TopicType<T>::descriptor(), name.c_str(),
                                            qos != nullptr ? qos->get() : nullptr, nullptr);
    if (t < 0) {
      return dds_error(t, fmt::format("dds_create_topic({})", name));
    }
    return Topic{Entity{t}, std::move(name)};
  }

  // Which samples the readers of this topic take in (a content filter on the reader side, as a
  // ContentFilteredTopic of DDS 1.4 §2.2.2.3.3 is): Cyclone drops a sample `accept` refuses
  // before it reaches a reader's history, so it makes no instance and calls no listener. It
  // still crosses the network: the writer sends to every matched reader. Set it before the
  // topic's readers are created and keep the topic for readers only (Cyclone also filters a
  // writer's writes through it). The topic must outlive its readers. `accept` runs on
  // Cyclone's receive thread: it must not block.
  using Filter = std::function<bool(const T& sample)>;
  Status set_filter(Filter accept) {
    auto filter = std::make_unique<Filter>(std::move(accept));
    const dds_return_t rc = dds_set_topic_filter_and_arg(handle(), &Topic::apply, filter.get());
    if (rc != DDS_RETCODE_OK) {
      return dds_error(rc, fmt::format("dds_set_topic_filter_and_arg({})", name_));
    }
    filter_ = std::move(filter);  // the old filter (if any) is no longer referenced
    return {};
  }

  [[nodiscard]] dds_entity_t handle() const { return entity_.get(); }
  [[nodiscard]] const std::string& name() const { return name_; }

 private:
  Topic(Entity e, std::string name) : entity_(std::move(e)), name_(std::move(name)) {}
  static bool apply(const void* sample, void* filter) {
    return (*static_cast<const Filter*>(filter))(*static_cast<const T*>(sample));
  }
  Entity entity_;
  std::string name_;
  std::unique_ptr<Filter> filter_;  // a stable address for Cyclone, however the topic moves
};

}  // namespace sf::dds

// Binds an idlc-generated C type to its descriptor (CType##_desc).
#define SF_DDS_TOPIC_TYPE(CType)                                               \
  template <>                                                                  \
  struct sf::dds::TopicType<CType> {                                           \
    static const dds_topic_descriptor_t& descriptor() { return CType##_desc; } \
  }
