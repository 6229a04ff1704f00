#pragma once
// Entity handles: a slot index plus a generation. Destroying an entity bumps its slot's generation,
// so every handle issued before stays invalid forever, even after the index is reused.
#include <compare>
#include <cstdint>
#include <functional>
#include <limits>

#include <fmt/format.h>

namespace engine::ecs {

struct Entity {
  static constexpr std::uint32_t kNullIndex = std::numeric_limits<std::uint32_t>::max();

  std::uint32_t index = kNullIndex;
  std::uint32_t generation = 0;

  static constexpr Entity null() { return Entity{}; }
  constexpr bool isNull() const { return index == kNullIndex; }

  // One 64-bit value (generation in the high half): for hashing, sorting and serialization.
  constexpr std::uint64_t bits() const {
    return (std::uint64_t{generation} << 32U) | std::uint64_t{index};
  }
  static constexpr Entity fromBits(std::uint64_t bits) {
    return Entity{static_cast<std::uint32_t>(bits & 0xFFFFFFFFU), static_cast<std::uint32_t>(bits >> 32U)};
  }

  // Ordered by index, then generation.
  friend constexpr auto operator<=>(const Entity&, const Entity&) = default;
};

inline constexpr Entity kNullEntity = Entity::null();

}  // namespace engine::ecs

template <>
struct std::hash<engine::ecs::Entity> {
  std::size_t operator()(engine::ecs::Entity e) const noexcept { return std::hash<std::uint64_t>{}(e.bits()); }
};

// Formats as "index:generation" ("null" for the null entity), e.g. in log messages.
template <>
struct fmt::formatter<engine::ecs::Entity> : fmt::formatter<std::string_view> {
  template <class FormatContext>
  auto format(engine::ecs::Entity e, FormatContext& ctx) const {
    if (e.isNull()) return fmt::format_to(ctx.out(), "null");
    return fmt::format_to(ctx.out(), "{}:{}", e.index, e.generation);
  }
};
