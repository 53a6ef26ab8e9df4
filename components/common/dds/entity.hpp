#pragma once
// Move-only owner of a dds_entity_t; deletes it (and its children) on destruction.

#include <cstdint>
#include <utility>

namespace stereoball::dds {

using EntityHandle = int32_t;  // dds_entity_t

class Entity {
 public:
  Entity() = default;
  explicit Entity(EntityHandle handle) : handle_(handle) {}
  ~Entity() { reset(); }
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, 0);
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;

  EntityHandle handle() const { return handle_; }
  explicit operator bool() const { return handle_ > 0; }
  void reset();

 private:
  EntityHandle handle_ = 0;
};

}  // namespace stereoball::dds
