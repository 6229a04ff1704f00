// The pipeline cache file's checks (engine/gpu/pipeline_cache.h), without a device: the bytes a
// driver would be handed from a file that is cut short, damaged, garbage or from another device.
// Every one of those must be refused with a reason before a driver sees it, and the file this
// engine wrote must come back byte for byte.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "engine/gpu/pipeline_cache.h"

namespace engine::gpu {
namespace {

PipelineCacheIdentity identity() {
  PipelineCacheIdentity id;
  id.vendorID = 0x10005;
  id.deviceID = 0x0000;
  for (std::size_t i = 0; i < id.uuid.size(); ++i) id.uuid[i] = std::uint8_t(0xa0 + i);
  return id;
}

void putU32(std::vector<std::uint8_t>& bytes, std::size_t offset, std::uint32_t value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(value));
}

// What a driver's vkGetPipelineCacheData returns: VkPipelineCacheHeaderVersionOne, then its blobs.
std::vector<std::uint8_t> driverData(const PipelineCacheIdentity& id, std::size_t bodyBytes = 200) {
  std::vector<std::uint8_t> bytes(16 + VK_UUID_SIZE + bodyBytes);
  putU32(bytes, 0, 16 + VK_UUID_SIZE);
  putU32(bytes, 4, VK_PIPELINE_CACHE_HEADER_VERSION_ONE);
  putU32(bytes, 8, id.vendorID);
  putU32(bytes, 12, id.deviceID);
  std::memcpy(bytes.data() + 16, id.uuid.data(), VK_UUID_SIZE);
  for (std::size_t i = 16 + VK_UUID_SIZE; i < bytes.size(); ++i) bytes[i] = std::uint8_t(i * 7);
  return bytes;
}

std::string refusal(const std::vector<std::uint8_t>& file) {
  const auto data = unsealPipelineCacheData(file, identity());
  return data ? std::string() : data.error().message;
}

// Tricky: the file must round-trip to exactly the driver's bytes (the footer is not handed to the
// driver), and an empty cache (a driver with nothing to keep still writes its header) too.
TEST(PipelineCacheFileTest, WhatWasSealedComesBackWhole) {
  for (const std::size_t body : {std::size_t(0), std::size_t(1), std::size_t(4096)}) {
    const std::vector<std::uint8_t> data = driverData(identity(), body);
    const std::vector<std::uint8_t> file = sealPipelineCacheData(data);
    const auto unsealed = unsealPipelineCacheData(file, identity());
    ASSERT_TRUE(unsealed.ok()) << unsealed.error().message;
    EXPECT_EQ(std::vector<std::uint8_t>(unsealed->begin(), unsealed->end()), data);
  }
}

// Tricky: a save interrupted part-way leaves a prefix whose driver header still looks right; only
// the footer can tell. Every length short of the whole file is refused, the empty file included.
TEST(PipelineCacheFileTest, EveryTruncationIsRefused) {
  const std::vector<std::uint8_t> file = sealPipelineCacheData(driverData(identity(), 64));
  for (std::size_t length = 0; length < file.size(); ++length) {
    const std::vector<std::uint8_t> cut(file.begin(), file.begin() + std::ptrdiff_t(length));
    EXPECT_FALSE(refusal(cut).empty()) << "a file cut to " << length << " of " << file.size() << " bytes was accepted";
  }
}

// Tricky: one flipped bit inside the driver's blobs (not its header) is what a driver would be
// least likely to notice; the checksum must.
TEST(PipelineCacheFileTest, ADamagedByteIsRefused) {
  const std::vector<std::uint8_t> data = driverData(identity(), 64);
  for (const std::size_t at : {std::size_t(0), std::size_t(20), data.size() - 1}) {
    std::vector<std::uint8_t> file = sealPipelineCacheData(data);
    file[at] ^= 0x10;
    EXPECT_FALSE(refusal(file).empty()) << "byte " << at << " damaged";
  }
}

// Tricky: a whole, undamaged file from another GPU, another driver build or another header
// version passes the footer; the driver's header must refuse it, each field on its own.
TEST(PipelineCacheFileTest, AnotherDeviceOrDriverIsRefusedByTheHeader) {
  struct Case {
    const char* what;
    std::size_t offset;
    std::uint32_t value;
    const char* reasonNames;
  };
  for (const Case c : {Case{"vendor", 8, 0x10de, "vendor"}, Case{"device", 12, 0x2204, "device"},
                       Case{"header version", 4, 2, "version"}, Case{"header size", 0, 8, "header size"},
                       Case{"header size past the data", 0, 100000, "header size"}}) {
    std::vector<std::uint8_t> data = driverData(identity());
    putU32(data, c.offset, c.value);
    const std::string why = refusal(sealPipelineCacheData(data));
    EXPECT_NE(why.find(c.reasonNames), std::string::npos) << c.what << ": '" << why << "'";
  }
  std::vector<std::uint8_t> data = driverData(identity());
  data[16 + 5] ^= 1;
  EXPECT_NE(refusal(sealPipelineCacheData(data)).find("pipelineCacheUUID"), std::string::npos);
  // A driver's bytes too short to hold its header at all, footer intact.
  const std::vector<std::uint8_t> shortData(12, 0);
  EXPECT_NE(refusal(sealPipelineCacheData(shortData)).find("shorter than a cache header"), std::string::npos);
}

// Tricky (fuzz-ish): random bytes of random lengths, with and without a valid footer around them,
// must be refused without reading past their end (the ASan build would catch that).
TEST(PipelineCacheFileTest, GarbageIsRefused) {
  std::mt19937 random(34);
  for (int i = 0; i < 2000; ++i) {
    std::vector<std::uint8_t> bytes(random() % 256);
    for (std::uint8_t& byte : bytes) byte = std::uint8_t(random());
    EXPECT_FALSE(refusal(bytes).empty()) << "garbage " << i;
    EXPECT_FALSE(refusal(sealPipelineCacheData(bytes)).empty()) << "sealed garbage " << i;
  }
}

}  // namespace
}  // namespace engine::gpu
