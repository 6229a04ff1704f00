#pragma once
// Component storage: one sparse set per component type.
//
// A SparseSet keeps its entities packed in a dense array (iteration touches only live data) and maps
// an entity index to its dense position through a paged sparse array (memory grows with the largest
// index in use, one page at a time, not with the index space). Removal is swap-and-pop: the last
// element moves into the hole, so removal is O(1) and the arrays stay packed.
//
// Storage<C> adds the components, in the same dense order. They live in fixed-size pages that never
// reallocate, so emplacing never moves existing components: a reference obtained from get() stays
// valid until that component is removed or another component of the same type is removed (the
// swap-and-pop may move it) or the storage is cleared.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/ecs/entity.h"

namespace engine::ecs {

namespace detail {

inline std::uint32_t nextComponentTypeId() {
  static std::atomic<std::uint32_t> next{0};
  return next.fetch_add(1, std::memory_order_relaxed);
}

// A readable type name for error messages, without RTTI (GCC and Clang spell it in the signature).
template <class T>
constexpr std::string_view typeName() {
  const std::string_view signature = __PRETTY_FUNCTION__;
  const std::size_t start = signature.find("T = ");
  if (start == std::string_view::npos) return "component";
  const std::size_t end = signature.find_first_of(";]", start);
  return signature.substr(start + 4, end - start - 4);
}

// Builds a T from args: with a constructor when T has a matching one, else as an aggregate (so
// emplace<Position>(e, 1.0f, 2.0f) works for plain structs on compilers without C++20's
// parenthesized aggregate initialization, e.g. Clang 14).
template <class T, class... A>
T makeValue(A&&... args) {
  if constexpr (std::is_constructible_v<T, A&&...>) {
    return T(std::forward<A>(args)...);
  } else {
    return T{std::forward<A>(args)...};
  }
}

[[noreturn]] inline void throwContractViolation(const std::string& message) { throw std::logic_error(message); }

}  // namespace detail

// Dense ids 0, 1, 2, ... assigned on first use, so a registry can index its storages by them.
template <class C>
std::uint32_t componentTypeId() {
  static const std::uint32_t id = detail::nextComponentTypeId();
  return id;
}

class SparseSet {
 public:
  SparseSet() = default;
  SparseSet(const SparseSet&) = delete;
  SparseSet& operator=(const SparseSet&) = delete;
  virtual ~SparseSet() = default;

  // True only for this exact handle: a stale handle with the same index but another generation is absent.
  bool contains(Entity e) const {
    const std::uint32_t position = positionOf(e.index);
    return position != kNoPosition && dense_[position] == e;
  }
  std::size_t size() const { return dense_.size(); }
  bool empty() const { return dense_.empty(); }
  std::span<const Entity> entities() const { return dense_; }  // in dense (storage) order

  // Removes e and its component; false if e is not here.
  virtual bool remove(Entity e) = 0;
  virtual void clear() = 0;

 protected:
  static constexpr std::uint32_t kNoPosition = std::numeric_limits<std::uint32_t>::max();

  std::uint32_t positionOf(std::uint32_t index) const {
    const std::size_t page = index / kPageSize;
    if (page >= sparse_.size() || !sparse_[page]) return kNoPosition;
    return (*sparse_[page])[index % kPageSize];
  }
  void pushEntity(Entity e);
  // Swap-and-pop of the entity at `position`: the last entity takes its place.
  void eraseEntityAt(std::uint32_t position);
  void clearEntities();

 private:
  static constexpr std::size_t kPageSize = 4096;
  using Page = std::array<std::uint32_t, kPageSize>;

  std::uint32_t& sparseSlot(std::uint32_t index);

  std::vector<std::unique_ptr<Page>> sparse_;
  std::vector<Entity> dense_;
};

// A vector whose elements never move: fixed-capacity pages, appended and popped at the back.
template <class T>
class PagedVector {
 public:
  static constexpr std::size_t kPageSize = std::bit_floor(std::max<std::size_t>(16384 / sizeof(T), 1));

  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return pages_[i / kPageSize][i % kPageSize]; }
  const T& operator[](std::size_t i) const { return pages_[i / kPageSize][i % kPageSize]; }

  template <class... A>
  T& emplaceBack(A&&... args) {
    if (size_ / kPageSize == pages_.size()) {
      pages_.emplace_back();
      pages_.back().reserve(kPageSize);  // never exceeded, so the page never reallocates
    }
    std::vector<T>& page = pages_[size_ / kPageSize];
    T* element = nullptr;
    if constexpr (std::is_constructible_v<T, A&&...>) {
      element = &page.emplace_back(std::forward<A>(args)...);
    } else {
      element = &page.emplace_back(detail::makeValue<T>(std::forward<A>(args)...));
    }
    ++size_;
    return *element;
  }
  void popBack() {
    --size_;
    pages_[size_ / kPageSize].pop_back();
  }
  void clear() {
    pages_.clear();
    size_ = 0;
  }

 private:
  std::vector<std::vector<T>> pages_;
  std::size_t size_ = 0;
};

template <class C>
class Storage final : public SparseSet {
  static_assert(std::is_same_v<C, std::remove_cvref_t<C>>, "components are plain (non-const, non-reference) types");
  static_assert(std::is_move_constructible_v<C> && std::is_move_assignable_v<C>,
                "swap-and-pop removal moves components: they must be move-constructible and move-assignable");

 public:
  // Precondition: !contains(e) (the registry checks).
  template <class... A>
  C& emplace(Entity e, A&&... args) {
    C& component = components_.emplaceBack(std::forward<A>(args)...);
    try {
      pushEntity(e);
    } catch (...) {
      components_.popBack();
      throw;
    }
    return component;
  }

  // Precondition: contains(e).
  C& get(Entity e) { return components_[positionOf(e.index)]; }
  const C& get(Entity e) const { return components_[positionOf(e.index)]; }

  C* tryGet(Entity e) { return contains(e) ? &components_[positionOf(e.index)] : nullptr; }
  const C* tryGet(Entity e) const { return contains(e) ? &components_[positionOf(e.index)] : nullptr; }

  bool remove(Entity e) override {
    if (!contains(e)) return false;
    const std::uint32_t position = positionOf(e.index);
    const std::size_t last = components_.size() - 1;
    if (position != last) components_[position] = std::move(components_[last]);
    components_.popBack();
    eraseEntityAt(position);
    return true;
  }

  void clear() override {
    components_.clear();
    clearEntities();
  }

 private:
  PagedVector<C> components_;
};

}  // namespace engine::ecs
