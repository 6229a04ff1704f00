#pragma once
// A list of things in a message: the first few by name, then how many more. A warning about a
// level's thousands of nodes or a character's dozens of animations names a few, not all of them.
#include <cstddef>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace engine {

// How many a message names before it counts the rest.
inline constexpr std::size_t kNamedInMessages = 4;

// `named` (the first kNamedInMessages or fewer of `total` things), then "N more" for the rest:
// "a, b, c, d, 3 more".
inline std::string namedList(const std::vector<std::string>& named, std::size_t total) {
  std::string text = fmt::format("{}", fmt::join(named, ", "));
  if (total > named.size()) text += fmt::format("{}{} more", named.empty() ? "" : ", ", total - named.size());
  return text;
}

}  // namespace engine
