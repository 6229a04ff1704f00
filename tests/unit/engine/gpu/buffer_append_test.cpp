// engine::gpu::appendToBuffers (engine/gpu/buffer.h): data appended after what a buffer holds, in
// place while it fits, else in a larger buffer that keeps the old bytes; the replaced buffer handed
// back to outlive the work that reads it; a failed allocation leaving every buffer as it was; each
// append's writer filling its bytes straight into the staging memory; room reserved for data
// copied on the GPU from another buffer (engine::gpu::recordBufferCopies).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

#include "engine/gpu/buffer.h"
#include "engine/gpu/vk_check.h"
#include "gpu_fault_support.h"

namespace engine::gpu {
namespace {

constexpr VkBufferUsageFlags kUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;

std::vector<std::uint32_t> iota(std::uint32_t first, std::size_t count) {
  std::vector<std::uint32_t> values(count);
  std::iota(values.begin(), values.end(), first);
  return values;
}

std::vector<std::uint32_t> readWords(const Context& context, const Buffer& buffer, std::size_t count) {
  const std::vector<std::uint8_t> bytes = readbackBuffer(context, buffer);
  std::vector<std::uint32_t> words(count);
  std::memcpy(words.data(), bytes.data(), count * sizeof(std::uint32_t));
  return words;
}

BufferAppend appendOf(Buffer& buffer, std::size_t usedWords, const std::vector<std::uint32_t>& words) {
  const std::span<const std::byte> bytes = std::as_bytes(std::span(words));
  return {&buffer, usedWords * sizeof(std::uint32_t), bytes.size(), copyOf(bytes), kUsage, "append test"};
}

// Tricky: three appends to two buffers, one of them starting empty: the first fills exactly (no
// room to spare from nothing), the second grows (the old words copied on the GPU, room for half as
// much again, the old buffer handed back), the third fits the room the growth left and must keep
// the very buffer (its address stays valid for commands recorded before).
TEST(BufferAppend, KeepsWhatIsThereGrowsByHalfAndFillsTheRoomInPlace) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  Buffer empty, other;
  const auto a = iota(0, 100), b = iota(1000, 60), c = iota(5000, 40), d = iota(9000, 7);
  std::vector<BufferAppend> first{appendOf(empty, 0, a), appendOf(other, 0, d)};
  EXPECT_TRUE(appendToBuffers(*context, first).empty());
  ASSERT_TRUE(empty);
  EXPECT_EQ(empty.size(), 100u * 4u);

  std::vector<BufferAppend> second{appendOf(empty, 100, b)};
  std::vector<Buffer> replaced = appendToBuffers(*context, second);
  ASSERT_EQ(replaced.size(), 1u);
  EXPECT_EQ(replaced[0].size(), 100u * 4u);
  EXPECT_EQ(empty.size(), 160u * 4u) << "room for half as much again: 150 words, short of the 160 needed";
  replaced.clear();

  std::vector<BufferAppend> third{appendOf(empty, 160, iota(7000, 0))};
  EXPECT_TRUE(appendToBuffers(*context, third).empty()) << "nothing to append";
  std::vector<BufferAppend> grow{appendOf(empty, 160, c)};
  replaced = appendToBuffers(*context, grow);
  ASSERT_EQ(replaced.size(), 1u);
  EXPECT_EQ(empty.size(), 240u * 4u) << "half as much again as 160 words";
  const VkBuffer kept = empty.handle();
  std::vector<BufferAppend> fits{appendOf(empty, 200, d)};
  EXPECT_TRUE(appendToBuffers(*context, fits).empty());
  EXPECT_EQ(empty.handle(), kept);

  std::vector<std::uint32_t> expected = a;
  expected.insert(expected.end(), b.begin(), b.end());
  expected.insert(expected.end(), c.begin(), c.end());
  expected.insert(expected.end(), d.begin(), d.end());
  EXPECT_EQ(readWords(*context, empty, expected.size()), expected);
  EXPECT_EQ(readWords(*context, other, d.size()), d);
  EXPECT_EQ(context->validationMessageCount(), 0u) << ::testing::PrintToString(context->validationMessages());
}

// Tricky: data written in parts (a large upload spread over frames) reserves its whole size with
// the first part, so the later parts fill that buffer in place: no growth copies the parts already
// written, and the buffer keeps its handle (commands recorded meanwhile stay valid). A reserve
// smaller than the part changes nothing.
TEST(BufferAppend, AReserveMakesRoomForTheLaterParts) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  Buffer buffer;
  const auto a = iota(0, 30), b = iota(100, 30), c = iota(200, 40);
  std::vector<BufferAppend> first{appendOf(buffer, 0, a)};
  first[0].reserve = 100 * sizeof(std::uint32_t);
  EXPECT_TRUE(appendToBuffers(*context, first).empty());
  EXPECT_EQ(buffer.size(), 100u * 4u) << "made with room for the whole upload";
  const VkBuffer made = buffer.handle();
  std::vector<BufferAppend> second{appendOf(buffer, 30, b)};
  second[0].reserve = 70 * sizeof(std::uint32_t);
  std::vector<BufferAppend> third{appendOf(buffer, 60, c)};
  third[0].reserve = 4;  // less than the part: the part's own size counts
  EXPECT_TRUE(appendToBuffers(*context, second).empty());
  EXPECT_TRUE(appendToBuffers(*context, third).empty());
  EXPECT_EQ(buffer.handle(), made) << "a later part grew the buffer";
  std::vector<std::uint32_t> expected = a;
  expected.insert(expected.end(), b.begin(), b.end());
  expected.insert(expected.end(), c.begin(), c.end());
  EXPECT_EQ(readWords(*context, buffer, expected.size()), expected);
  EXPECT_EQ(context->validationMessageCount(), 0u) << ::testing::PrintToString(context->validationMessages());
}

// Tricky: the second buffer's growth does not fit the budget after the first's did: neither may
// change (the first's larger buffer given back, its words as they were), and with the budget
// lifted the same append succeeds. A buffer said to hold more than it has is refused by name.
TEST(BufferAppend, AFailedAllocationLeavesEveryBufferAsItWas) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  Buffer small, large;
  const auto a = iota(0, 16), b = iota(100, 4096), more = iota(20000, 8192);
  std::vector<BufferAppend> first{appendOf(small, 0, a), appendOf(large, 0, b)};
  (void)appendToBuffers(*context, first);
  Allocator& allocator = context->allocator();
  allocator.setBudget(allocator.stats().usedBytes + 16 * 1024);  // the small one's growth, not the large one's
  std::vector<BufferAppend> both{appendOf(small, 16, a), appendOf(large, 4096, more)};
  const VkBuffer smallBefore = small.handle(), largeBefore = large.handle();
  const VkDeviceSize usedBefore = allocator.stats().usedBytes;
  EXPECT_THROW((void)appendToBuffers(*context, both), VulkanError);
  EXPECT_EQ(small.handle(), smallBefore);
  EXPECT_EQ(large.handle(), largeBefore);
  EXPECT_EQ(allocator.stats().usedBytes, usedBefore) << "the grown small buffer was not given back";
  allocator.setBudget(Allocator::kUnlimited);
  EXPECT_EQ(readWords(*context, small, a.size()), a);
  EXPECT_EQ(readWords(*context, large, b.size()), b);

  std::vector<BufferAppend> again{appendOf(small, 16, a), appendOf(large, 4096, more)};
  EXPECT_EQ(appendToBuffers(*context, again).size(), 2u);
  std::vector<std::uint32_t> expected = b;
  expected.insert(expected.end(), more.begin(), more.end());
  EXPECT_EQ(readWords(*context, large, expected.size()), expected);

  std::vector<BufferAppend> wrong{appendOf(small, 1000, a)};
  try {
    (void)appendToBuffers(*context, wrong);
    FAIL() << "a buffer said to hold more than its size was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'append test'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(context->validationMessageCount(), 0u) << ::testing::PrintToString(context->validationMessages());
}

// Tricky: the appends share one staging buffer as large as the largest of them, so a writer could
// be handed the whole staging memory, or called again for a later buffer. Each writer must get
// exactly its own byte count, once, and what it writes (from two sources, changed on the way, as
// the cell feature writes its assets' records) must land after the bytes already there. Bytes
// without a writer are refused by name, before any buffer is touched.
TEST(BufferAppend, EachWriterFillsExactlyItsBytesOnceStraightIntoTheBuffer) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  Buffer small, large;
  const auto held = iota(0, 8), left = iota(100, 500), right = iota(900, 300), tail = iota(50, 3);
  std::vector<BufferAppend> first{appendOf(small, 0, held), appendOf(large, 0, held)};
  (void)appendToBuffers(*context, first);

  std::vector<std::size_t> calls(2, 0), spans(2, 0);
  const auto twoSources = [&](std::span<std::byte> out) {  // left, then right with its words doubled
    ++calls[0];
    spans[0] = out.size();
    std::memcpy(out.data(), left.data(), left.size() * sizeof(std::uint32_t));
    for (std::size_t i = 0; i < right.size(); ++i) {
      const std::uint32_t word = 2 * right[i];
      std::memcpy(out.data() + (left.size() + i) * sizeof(std::uint32_t), &word, sizeof(word));
    }
  };
  const auto threeWords = [&](std::span<std::byte> out) {
    ++calls[1];
    spans[1] = out.size();
    std::memcpy(out.data(), tail.data(), std::min(out.size(), tail.size() * sizeof(std::uint32_t)));
  };
  const VkDeviceSize word = sizeof(std::uint32_t);
  std::vector<BufferAppend> appends{
      {&large, held.size() * word, (left.size() + right.size()) * word, twoSources, kUsage, "two sources"},
      {&small, held.size() * word, tail.size() * word, threeWords, kUsage, "three words"}};
  (void)appendToBuffers(*context, appends);
  EXPECT_EQ(calls, (std::vector<std::size_t>{1, 1}));
  EXPECT_EQ(spans, (std::vector<std::size_t>{800 * word, 3 * word}));

  std::vector<std::uint32_t> expected = held;
  expected.insert(expected.end(), left.begin(), left.end());
  for (std::uint32_t w : right) expected.push_back(2 * w);
  EXPECT_EQ(readWords(*context, large, expected.size()), expected);
  expected = held;
  expected.insert(expected.end(), tail.begin(), tail.end());
  EXPECT_EQ(readWords(*context, small, expected.size()), expected);

  const VkBuffer before = small.handle();
  std::vector<BufferAppend> noWriter{{&small, 11 * word, 64 * word, {}, kUsage, "no writer"}};
  try {
    (void)appendToBuffers(*context, noWriter);
    FAIL() << "bytes without a writer were taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'no writer'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(small.handle(), before);
  EXPECT_EQ(context->validationMessageCount(), 0u) << ::testing::PrintToString(context->validationMessages());
}

// Tricky: a buffer rebuilt from an older one (the cell feature's rebuild) gets part of its data
// from the CPU and the rest copied on the GPU from the old buffer, region by region, into the room
// the append reserved. A buffer whose data all comes by copies gets no bytes at all, yet must be
// made with its room; a buffer grown with no bytes added must keep the bytes it held. The copies,
// recorded in a command buffer, land where their regions say, each of several, beside the bytes
// the CPU wrote.
TEST(BufferAppend, RoomReservedWithoutDataIsMadeAndFilledByCopiesOnTheGpu) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  const VkDeviceSize word = sizeof(std::uint32_t);
  Buffer old, written, copiedOnly, grown;
  const auto held = iota(0, 90), fresh = iota(5000, 10), kept = iota(700, 12);
  std::vector<BufferAppend> first{appendOf(old, 0, held), appendOf(grown, 0, kept)};
  (void)appendToBuffers(*context, first);

  std::vector<BufferAppend> rebuilt{appendOf(written, 0, fresh), appendOf(copiedOnly, 0, iota(0, 0))};
  rebuilt[0].reserve = 50 * word;  // 10 words written, 40 copied after them
  rebuilt[1].reserve = 30 * word;  // all 30 copied
  EXPECT_TRUE(appendToBuffers(*context, rebuilt).empty()) << "new buffers replace none";
  ASSERT_TRUE(written);
  ASSERT_TRUE(copiedOnly) << "a buffer with room and no data was not made";
  EXPECT_EQ(written.size(), 50u * word);
  EXPECT_EQ(copiedOnly.size(), 30u * word);

  std::vector<BufferAppend> roomOnly{appendOf(grown, kept.size(), iota(0, 0))};
  roomOnly[0].reserve = 100 * word;
  EXPECT_EQ(appendToBuffers(*context, roomOnly).size(), 1u) << "grown for its room";
  EXPECT_EQ(grown.size(), 112u * word);
  EXPECT_EQ(readWords(*context, grown, kept.size()), kept) << "a grown buffer lost its bytes";

  // Words 60..84 and 5..19 of `old` after the written words; words 30..59 into the other.
  const std::vector<BufferCopy> copies{
      {&old, &written, {{60 * word, 10 * word, 25 * word}, {5 * word, 35 * word, 15 * word}}},
      {&old, &copiedOnly, {{30 * word, 0, 30 * word}}},
      {&old, &grown, {}}};  // no region: nothing recorded
  context->submitAndWait([&](VkCommandBuffer cmd) { recordBufferCopies(cmd, copies); });
  std::vector<std::uint32_t> expected = fresh;
  expected.insert(expected.end(), held.begin() + 60, held.begin() + 85);
  expected.insert(expected.end(), held.begin() + 5, held.begin() + 20);
  EXPECT_EQ(readWords(*context, written, expected.size()), expected);
  EXPECT_EQ(readWords(*context, copiedOnly, 30), std::vector<std::uint32_t>(held.begin() + 30, held.begin() + 60));
  EXPECT_EQ(context->validationMessageCount(), 0u) << ::testing::PrintToString(context->validationMessages());
}

}  // namespace
}  // namespace engine::gpu
