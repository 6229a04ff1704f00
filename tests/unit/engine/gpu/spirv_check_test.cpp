// The loader's SPIR-V check (engine/gpu/spirv_check.h) on a real module of this build and on the
// ways a file goes wrong during a hot reload: text in place of SPIR-V, a short file, and a file cut
// off while the shader build was writing it. No device: the check runs before the driver sees the
// bytes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/core/files.h"
#include "engine/gpu/spirv_check.h"

#ifndef HSDF_SHADER_OUTPUT_DIR
#error "HSDF_SHADER_OUTPUT_DIR must be defined by the build"
#endif

namespace engine::gpu {
namespace {

std::vector<std::uint8_t> builtShader(const std::string& name) {
  auto bytes = readBinaryFile(std::filesystem::path(HSDF_SHADER_OUTPUT_DIR) / name, 64u << 20);
  EXPECT_TRUE(bytes.ok()) << bytes.error().message;
  return bytes ? *bytes : std::vector<std::uint8_t>{};
}

std::uint32_t word(const std::vector<std::uint8_t>& bytes, std::size_t index) {
  return std::uint32_t(bytes[4 * index]) | std::uint32_t(bytes[4 * index + 1]) << 8 |
         std::uint32_t(bytes[4 * index + 2]) << 16 | std::uint32_t(bytes[4 * index + 3]) << 24;
}

std::string messageOf(const Status& status) { return status ? std::string("accepted") : status.error().message; }

TEST(SpirvCheck, AcceptsTheBuildsShaders) {
  for (const char* name : {"mesh.frag.spv", "mesh.vert.spv", "cells_resolve.frag.spv"}) {
    const std::vector<std::uint8_t> bytes = builtShader(name);
    ASSERT_FALSE(bytes.empty()) << name;
    EXPECT_TRUE(checkSpirv(bytes).ok()) << name << ": " << messageOf(checkSpirv(bytes));
  }
}

// Tricky: a file cut at a whole word still has the header and whole words, so the size and magic
// checks pass; only the instruction walk sees it. Every cut is refused except one right after an
// OpFunctionEnd that is not the module's last (a whole earlier function: documented as not seen).
// The test finds those cut points with its own walk of the instruction stream and expects exactly
// them, so a check that let a cut through elsewhere, or refused a whole module, fails.
TEST(SpirvCheck, RefusesEveryTruncationExceptAtAnEarlierFunctionsEnd) {
  const std::vector<std::uint8_t> whole = builtShader("cells_resolve.frag.spv");
  ASSERT_GT(whole.size(), 400u);
  const std::size_t words = whole.size() / 4;
  std::vector<bool> afterFunctionEnd(words + 1, false);
  for (std::size_t at = 5; at < words;) {
    const std::uint32_t first = word(whole, at);
    ASSERT_GT(first >> 16, 0u);
    at += first >> 16;
    if ((first & 0xffffu) == 56u) afterFunctionEnd[at] = true;  // OpFunctionEnd
  }
  ASSERT_TRUE(afterFunctionEnd[words]) << "a shader module ends with OpFunctionEnd";
  for (std::size_t cut = 0; cut < words; ++cut) {
    const std::span<const std::uint8_t> prefix(whole.data(), 4 * cut);
    const Status status = checkSpirv(prefix);
    if (afterFunctionEnd[cut]) {
      EXPECT_TRUE(status.ok()) << "cut after a whole function at word " << cut;
    } else {
      ASSERT_FALSE(status.ok()) << "a cut at word " << cut << " of " << words << " passed";
      EXPECT_EQ(status.error().message.rfind("not SPIR-V", 0), 0u) << status.error().message;
    }
  }
  const Status half = checkSpirv(std::span<const std::uint8_t>(whole.data(), whole.size() / 2 / 4 * 4));
  EXPECT_NE(messageOf(half).find("truncated"), std::string::npos) << messageOf(half);
}

// Tricky: each refusal must name what was wrong, not only fail: the panel and the log show it.
TEST(SpirvCheck, NamesWhatIsWrong) {
  const std::vector<std::uint8_t> whole = builtShader("mesh.frag.spv");
  ASSERT_FALSE(whole.empty());
  EXPECT_NE(messageOf(checkSpirv({})).find("size 0"), std::string::npos);
  EXPECT_NE(messageOf(checkSpirv(std::span(whole.data(), 6))).find("size 6"), std::string::npos);
  const std::string text(64, 'x');
  const std::span<const std::uint8_t> textBytes(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  EXPECT_NE(messageOf(checkSpirv(textBytes)).find("no SPIR-V header"), std::string::npos);
  std::vector<std::uint8_t> zeroCount = whole;
  zeroCount[4 * 5 + 2] = 0;  // the first instruction's word count (high half of its first word)
  zeroCount[4 * 5 + 3] = 0;
  EXPECT_NE(messageOf(checkSpirv(zeroCount)).find("0 words at word 5"), std::string::npos) << messageOf(checkSpirv(zeroCount));
  std::vector<std::uint8_t> tail = whole;
  tail.insert(tail.end(), {0x00, 0x00, 0x01, 0x00});  // one more 1-word instruction: OpNop after the end
  EXPECT_NE(messageOf(checkSpirv(tail)).find("not OpFunctionEnd"), std::string::npos) << messageOf(checkSpirv(tail));
}

}  // namespace
}  // namespace engine::gpu
