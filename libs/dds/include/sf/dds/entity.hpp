// Entity: an owned Cyclone DDS entity handle (participant, topic, reader,
// writer, ...). dds_delete() runs on destruction; deleting an entity deletes
// its children and waits for listener callbacks that are running on it.
#pragma once

#include <string_view>
#include <utility>

#include <dds/dds.h>

#include "sf/core/result.hpp"

namespace sf::dds {

// Cyclone's negative return codes as our errors, e.g.
// "dds_create_reader(OP1_BID): Bad Parameter". rc >= 0 is not an error.
Error dds_error(dds_return_t rc, std::string_view what);

class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  ~Entity() { reset(); }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, 0);
    }
    return *this;
  }

  [[nodiscard]] dds_entity_t get() const { return handle_; }
  explicit operator bool() const { return handle_ > 0; }
  // Deletes the entity now (children too). Safe to call twice.
  void reset();

 private:
  dds_entity_t handle_ = 0;
};

// The Cyclone entity handle as it appears in errors and logs.
using InstanceHandle = dds_instance_handle_t;

}  // namespace sf::dds
