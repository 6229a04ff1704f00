#pragma once
// Registry: creates entities and stores their components (plain structs), one sparse set per type.
//
//   ecs::Registry registry;
//   ecs::Entity e = registry.create();
//   registry.emplace<Transform>(e);
//   registry.view<Transform, WorldTransform>().each([](ecs::Entity, Transform& t, WorldTransform& w) {...});
//
// Error policy: misuse is a programming error and throws std::logic_error naming the component type
// and entity, leaving the registry unchanged: emplace on a dead entity or on one that already has the
// component (use emplaceOrReplace to overwrite), get of a missing component or dead entity. Queries
// that may legitimately miss answer instead: valid, has, tryGet (nullptr), remove and destroy (false).
// Not thread-safe. View iteration rules: see view.h.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/ecs/entity.h"
#include "engine/ecs/sparse_set.h"
#include "engine/ecs/view.h"

namespace engine::ecs {

class Registry {
 public:
  Registry() = default;
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;
  Registry(Registry&&) noexcept = default;
  Registry& operator=(Registry&&) noexcept = default;
  ~Registry() = default;

  // Reuses the most recently freed index (with a newer generation) before growing.
  Entity create();
  // Removes all of e's components and invalidates every handle to it; false if e was not alive.
  bool destroy(Entity e);
  bool valid(Entity e) const;
  std::size_t alive() const { return alive_; }
  // Every entity index ever handed out is below this (size per-entity scratch arrays with it).
  std::size_t indexBound() const { return slots_.size(); }
  // Destroys every entity (old handles stay invalid); storages are kept, so views stay usable.
  void clear();

  template <class C, class... A>
  C& emplace(Entity e, A&&... args) {
    requireAlive<C>(e, "emplace");
    Storage<C>& storage = assure<C>();
    if (storage.contains(e)) {
      detail::throwContractViolation(fmt::format("Registry::emplace<{}>: entity {} already has one (use emplaceOrReplace)",
                                                 detail::typeName<C>(), e));
    }
    return storage.emplace(e, std::forward<A>(args)...);
  }

  template <class C, class... A>
  C& emplaceOrReplace(Entity e, A&&... args) {
    requireAlive<C>(e, "emplaceOrReplace");
    Storage<C>& storage = assure<C>();
    if (C* existing = storage.tryGet(e)) {
      // Built first: the arguments may refer to the component being replaced.
      C replacement = detail::makeValue<C>(std::forward<A>(args)...);
      *existing = std::move(replacement);
      return *existing;
    }
    return storage.emplace(e, std::forward<A>(args)...);
  }

  template <class C>
  C& get(Entity e) {
    return const_cast<C&>(std::as_const(*this).get<C>(e));
  }
  template <class C>
  const C& get(Entity e) const {
    const C* component = tryGet<C>(e);
    if (component == nullptr) {
      requireAlive<C>(e, "get");
      detail::throwContractViolation(
          fmt::format("Registry::get<{}>: entity {} has no such component", detail::typeName<C>(), e));
    }
    return *component;
  }

  // nullptr if e is dead or has no C.
  template <class C>
  C* tryGet(Entity e) {
    return const_cast<C*>(std::as_const(*this).tryGet<C>(e));
  }
  template <class C>
  const C* tryGet(Entity e) const {
    const Storage<C>* storage = find<C>();
    return storage == nullptr ? nullptr : storage->tryGet(e);
  }

  template <class C>
  bool has(Entity e) const {
    return tryGet<C>(e) != nullptr;
  }

  // False if e is dead or had no C.
  template <class C>
  bool remove(Entity e) {
    Storage<C>* storage = find<C>();
    return storage != nullptr && storage->remove(e);
  }

  // Number of entities that have a C.
  template <class C>
  std::size_t size() const {
    const Storage<C>* storage = find<C>();
    return storage == nullptr ? 0 : storage->size();
  }

  template <class... C>
  View<C...> view() {
    return View<C...>(&assure<std::remove_const_t<C>>()...);
  }
  template <class... C>
  View<const C...> view() const {
    return View<const C...>(find<std::remove_const_t<C>>()...);
  }

 private:
  struct Slot {
    std::uint32_t generation = 0;
    bool alive = false;
  };

  template <class C>
  static constexpr void checkComponentType() {
    static_assert(std::is_same_v<C, std::remove_cvref_t<C>>, "name the plain component type (no const, no reference)");
  }

  template <class C>
  Storage<C>& assure() {
    checkComponentType<C>();
    const std::uint32_t id = componentTypeId<C>();
    if (id >= storages_.size()) storages_.resize(id + 1);
    if (!storages_[id]) storages_[id] = std::make_unique<Storage<C>>();
    return static_cast<Storage<C>&>(*storages_[id]);
  }

  template <class C>
  const Storage<C>* find() const {
    checkComponentType<C>();
    const std::uint32_t id = componentTypeId<C>();
    return id < storages_.size() ? static_cast<const Storage<C>*>(storages_[id].get()) : nullptr;
  }
  template <class C>
  Storage<C>* find() {
    return const_cast<Storage<C>*>(std::as_const(*this).find<C>());
  }

  template <class C>
  void requireAlive(Entity e, const char* operation) const {
    if (!valid(e)) {
      detail::throwContractViolation(fmt::format("Registry::{}<{}>: entity {} is not alive", operation,
                                                 detail::typeName<C>(), e));
    }
  }

  void release(std::uint32_t index);

  std::vector<Slot> slots_;
  std::vector<std::uint32_t> freeIndices_;
  std::size_t alive_ = 0;
  std::vector<std::unique_ptr<SparseSet>> storages_;  // indexed by componentTypeId
};

}  // namespace engine::ecs
