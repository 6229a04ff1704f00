#include "engine/ecs/sparse_set.h"

namespace engine::ecs {

std::uint32_t& SparseSet::sparseSlot(std::uint32_t index) {
  const std::size_t page = index / kPageSize;
  if (page >= sparse_.size()) sparse_.resize(page + 1);
  if (!sparse_[page]) {
    sparse_[page] = std::make_unique<Page>();
    sparse_[page]->fill(kNoPosition);
  }
  return (*sparse_[page])[index % kPageSize];
}

void SparseSet::pushEntity(Entity e) {
  // Fail before touching anything if the dense array cannot grow, so the set stays consistent.
  if (dense_.size() >= kNoPosition) throw std::length_error("SparseSet: too many entities");
  std::uint32_t& slot = sparseSlot(e.index);
  dense_.push_back(e);
  slot = static_cast<std::uint32_t>(dense_.size() - 1);
}

void SparseSet::eraseEntityAt(std::uint32_t position) {
  const Entity removed = dense_[position];
  const Entity moved = dense_.back();
  dense_[position] = moved;
  sparseSlot(moved.index) = position;
  sparseSlot(removed.index) = kNoPosition;  // after the line above: removed may be the moved one
  dense_.pop_back();
}

void SparseSet::clearEntities() {
  dense_.clear();
  sparse_.clear();
}

}  // namespace engine::ecs
