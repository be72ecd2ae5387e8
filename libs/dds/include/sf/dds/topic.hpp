// Topic<T>: a named, typed topic over an idlc-generated C type. The type's
// descriptor is found through TopicType<T>, declared next to the generated
// header with SF_DDS_TOPIC_TYPE(sf_cnp_Announce).
#pragma once

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

  [[nodiscard]] dds_entity_t handle() const { return entity_.get(); }
  [[nodiscard]] const std::string& name() const { return name_; }

 private:
  Topic(Entity e, std::string name) : entity_(std::move(e)), name_(std::move(name)) {}
  Entity entity_;
  std::string name_;
};

}  // namespace sf::dds

// Binds an idlc-generated C type to its descriptor (CType##_desc).
#define SF_DDS_TOPIC_TYPE(CType)                                               \
  template <>                                                                  \
  struct sf::dds::TopicType<CType> {                                           \
    static const dds_topic_descriptor_t& descriptor() { return CType##_desc; } \
  }
