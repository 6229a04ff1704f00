#include "engine/gpu/spirv_check.h"

#include <cstring>

#include <fmt/format.h>

namespace engine::gpu {
namespace {

constexpr std::uint32_t kSpirvMagic = 0x07230203u;
constexpr std::size_t kHeaderWords = 5;  // magic, version, generator, bound, schema
constexpr std::uint32_t kOpFunctionEnd = 56;

std::uint32_t wordAt(std::span<const std::uint8_t> bytes, std::size_t index) {
  std::uint32_t word = 0;
  std::memcpy(&word, bytes.data() + 4 * index, sizeof(word));
  return word;
}

}  // namespace

Status checkSpirv(std::span<const std::uint8_t> bytes) {
  if (bytes.empty() || bytes.size() % 4 != 0) return makeError(fmt::format("not SPIR-V (size {})", bytes.size()));
  const std::size_t words = bytes.size() / 4;
  if (words < kHeaderWords || wordAt(bytes, 0) != kSpirvMagic)
    return makeError("not SPIR-V (no SPIR-V header: magic number 0x07230203 missing; rebuild the shaders)");
  std::size_t at = kHeaderWords;
  std::uint32_t lastOpcode = 0;
  while (at < words) {
    const std::uint32_t first = wordAt(bytes, at);
    const std::size_t count = first >> 16;
    if (count == 0) return makeError(fmt::format("not SPIR-V (an instruction of 0 words at word {})", at));
    if (at + count > words)
      return makeError(fmt::format("not SPIR-V (truncated: the instruction at word {} needs {} words, the file ends at "
                                   "word {}; rebuild the shaders)",
                                   at, count, words));
    lastOpcode = first & 0xffffu;
    at += count;
  }
  if (lastOpcode != kOpFunctionEnd)
    return makeError(fmt::format("not SPIR-V (truncated: {} words, the last instruction is opcode {}, not OpFunctionEnd; "
                                 "rebuild the shaders)",
                                 words, lastOpcode));
  return {};
}

}  // namespace engine::gpu
