#include "engine/ecs/registry.h"

#include <stdexcept>

namespace engine::ecs {

Entity Registry::create() {
  std::uint32_t index = 0;
  if (!freeIndices_.empty()) {
    index = freeIndices_.back();
    freeIndices_.pop_back();
  } else {
    if (slots_.size() >= Entity::kNullIndex) throw std::length_error("Registry::create: entity index space exhausted");
    index = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  slots_[index].alive = true;
  ++alive_;
  return Entity{index, slots_[index].generation};
}

bool Registry::valid(Entity e) const {
  return e.index < slots_.size() && slots_[e.index].alive && slots_[e.index].generation == e.generation;
}

bool Registry::destroy(Entity e) {
  if (!valid(e)) return false;
  for (const std::unique_ptr<SparseSet>& storage : storages_) {
    if (storage) storage->remove(e);
  }
  release(e.index);
  return true;
}

void Registry::clear() {
  for (const std::unique_ptr<SparseSet>& storage : storages_) {
    if (storage) storage->clear();
  }
  for (std::size_t index = slots_.size(); index-- > 0;) {
    if (slots_[index].alive) release(static_cast<std::uint32_t>(index));
  }
}

void Registry::release(std::uint32_t index) {
  Slot& slot = slots_[index];
  slot.alive = false;
  --alive_;
  // A slot whose generation would wrap is retired instead, so no handle can ever come back to life.
  if (slot.generation == std::numeric_limits<std::uint32_t>::max()) return;
  ++slot.generation;
  freeIndices_.push_back(index);
}

}  // namespace engine::ecs
