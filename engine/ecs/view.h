#pragma once
// View<C...>: the entities that have every component C, iterated with each() or range-for.
//
// Iteration guarantee (the view is a snapshot):
//   Creating a view records, in the order of the smallest of its storages, the entities that have
//   all of C at that moment. Iterating (each() or begin()/end()) visits those recorded entities that
//   STILL have all of C when their turn comes, each exactly once. So, inside the loop, anything may be
//   done to the registry: destroying or changing the current entity, destroying entities not yet
//   visited (they are skipped), creating entities and emplacing components (entities that join the
//   view are not visited in this pass; make a new view to see them). Iterating the same view again
//   walks the same record, filtered by the registry's state at that time.
// Component references handed to each() follow the Storage rule (sparse_set.h): emplacing never
// moves components; removing a component of the same type may move the one you hold.
//
// A View<const A, ...> (what a const Registry gives) hands out const components only.
#include <cstddef>
#include <iterator>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/ecs/sparse_set.h"

namespace engine::ecs {

template <class... C>
class View {
  static_assert(sizeof...(C) > 0, "a view needs at least one component type");

  template <class T>
  using StorageFor = std::conditional_t<std::is_const_v<T>, const Storage<std::remove_const_t<T>>,
                                        Storage<std::remove_const_t<T>>>;

 public:
  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Entity;
    using difference_type = std::ptrdiff_t;
    using pointer = const Entity*;
    using reference = const Entity&;

    Iterator() = default;
    reference operator*() const { return view_->snapshot_[position_]; }
    pointer operator->() const { return &view_->snapshot_[position_]; }
    Iterator& operator++() {
      ++position_;
      skipLeftEntities();
      return *this;
    }
    Iterator operator++(int) {
      Iterator before = *this;
      ++*this;
      return before;
    }
    friend bool operator==(const Iterator&, const Iterator&) = default;

   private:
    friend class View;
    Iterator(const View* view, std::size_t position) : view_(view), position_(position) { skipLeftEntities(); }
    void skipLeftEntities() {
      while (position_ < view_->snapshot_.size() && !view_->contains(view_->snapshot_[position_])) ++position_;
    }

    const View* view_ = nullptr;
    std::size_t position_ = 0;
  };

  // A null storage means no entity has that component yet: the view is empty.
  explicit View(StorageFor<C>*... storages) : storages_(storages...) { recordSnapshot(); }

  // f(Entity, C&...) or f(C&...), for each recorded entity that still has all of C.
  template <class F>
  void each(F&& f) const {
    for (const Entity e : snapshot_) {
      if (!contains(e)) continue;
      std::apply(
          [&](auto*... storage) {
            if constexpr (std::is_invocable_v<F&, Entity, C&...>) {
              f(e, storage->get(e)...);
            } else {
              static_assert(std::is_invocable_v<F&, C&...>, "each() wants f(Entity, C&...) or f(C&...)");
              f(storage->get(e)...);
            }
          },
          storages_);
    }
  }

  Iterator begin() const { return Iterator(this, 0); }
  Iterator end() const { return Iterator(this, snapshot_.size()); }

  // Whether e has all of C now (whether or not it was recorded).
  bool contains(Entity e) const {
    return std::apply([&](const auto*... storage) { return ((storage != nullptr && storage->contains(e)) && ...); },
                      storages_);
  }

  // The T component of e; T is one of C (its const-ness may be left out). Throws std::logic_error if
  // e has no T.
  template <class T>
  auto& get(Entity e) const {
    constexpr std::size_t kIndex = indexOf<std::remove_const_t<T>>();
    static_assert(kIndex < sizeof...(C), "View::get<T>: T is not one of the view's components");
    auto* storage = std::get<kIndex>(storages_);
    if (storage == nullptr || !storage->contains(e)) {
      detail::throwContractViolation(fmt::format("View::get<{}>: entity {} has no such component",
                                                 detail::typeName<std::remove_const_t<T>>(), e));
    }
    if constexpr (std::is_const_v<T>) {
      return std::as_const(storage->get(e));
    } else {
      return storage->get(e);
    }
  }

 private:
  template <class T>
  static constexpr std::size_t indexOf() {
    constexpr bool kMatches[] = {std::is_same_v<T, std::remove_const_t<C>>...};
    for (std::size_t i = 0; i < sizeof...(C); ++i) {
      if (kMatches[i]) return i;
    }
    return sizeof...(C);
  }

  void recordSnapshot() {
    const SparseSet* smallest = nullptr;
    bool anyMissing = false;
    std::apply(
        [&](const auto*... storage) {
          ((storage == nullptr ? void(anyMissing = true)
                               : void(smallest = (smallest == nullptr || storage->size() < smallest->size())
                                                     ? static_cast<const SparseSet*>(storage)
                                                     : smallest)),
           ...);
        },
        storages_);
    if (anyMissing) return;
    snapshot_.reserve(smallest->size());
    for (const Entity e : smallest->entities()) {
      if (contains(e)) snapshot_.push_back(e);
    }
  }

  std::tuple<StorageFor<C>*...> storages_;
  std::vector<Entity> snapshot_;
};

}  // namespace engine::ecs
