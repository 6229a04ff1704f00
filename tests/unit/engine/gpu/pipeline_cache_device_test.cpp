// The context's pipeline cache kept in a file (engine/gpu/pipeline_cache.h, ContextDesc::
// pipelineCacheFile) on the test device: saved when a context goes, seeding the next one, and a
// file that cannot be used logged and replaced, never an error nor a validation message.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/files.h"
#include "engine/gpu/context.h"
#include "engine/gpu/lazy_pipeline.h"
#include "engine/gpu/pipeline_cache.h"
#include "log_capture.h"
#include "mesh_prepass_pipeline.h"
#include "test_device.h"
#include "test_files.h"

namespace engine::gpu {
namespace {

class PipelineCacheDeviceTest : public ::testing::Test {
 protected:
  std::unique_ptr<Context> open(const std::filesystem::path& file) {
    ContextDesc desc;
    desc.applicationName = "pipeline cache test";
    const auto device = hsdftest::testDevicePreference();
    EXPECT_TRUE(device.ok());
    if (!device) return nullptr;
    desc.device = *device;
    desc.validation = true;
    desc.pipelineCacheFile = file;
    auto context = Context::create(desc);
    EXPECT_TRUE(context.ok()) << context.error().message;
    return context ? std::move(*context) : nullptr;
  }

  // Compiles mesh.vert with mesh_prepass.frag through the context's cache.
  static void compileOne(const Context& context) {
    LazyPipeline pipeline = describeMeshPrepass(context, "cached");
    ASSERT_TRUE(pipeline.described());
    ASSERT_TRUE(pipeline.get(context).ok());
  }

  // Destroys the context and returns the validation messages it reported, its destruction included.
  static std::uint64_t close(std::unique_ptr<Context>& context) { return hsdftest::messagesThroughDestruction(context); }

  // The driver's bytes in the file, as the device's identity reads them (empty: refused).
  static std::vector<std::uint8_t> driverBytes(const std::filesystem::path& file, const Context& context) {
    const auto bytes = readBinaryFile(file);
    if (!bytes) return {};
    const auto data = unsealPipelineCacheData(*bytes, pipelineCacheIdentity(context.physicalDevice()));
    return data ? std::vector<std::uint8_t>(data->begin(), data->end()) : std::vector<std::uint8_t>{};
  }
};

// Tricky: the file is written as the context is destroyed (after its last compile), and the next
// context must hand exactly the driver's bytes to the driver, not the file with its footer.
TEST_F(PipelineCacheDeviceTest, AContextSeedsTheNextOne) {
  const hsdftest::ScopedTempPath folder("pipeline_cache_round_trip");
  const std::filesystem::path file = folder.path() / "nested" / "pipelines.cache";
  auto first = open(file);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->pipelineCache().loadedBytes(), 0u) << "no file yet";
  compileOne(*first);
  EXPECT_EQ(close(first), 0u);
  ASSERT_TRUE(std::filesystem::exists(file));

  auto second = open(file);
  ASSERT_NE(second, nullptr);
  const std::vector<std::uint8_t> saved = driverBytes(file, *second);
  ASSERT_FALSE(saved.empty()) << "the saved file is refused by its own device";
  EXPECT_EQ(second->pipelineCache().loadedBytes(), saved.size());
  compileOne(*second);
  EXPECT_EQ(close(second), 0u);
}

// Tricky: garbage, a truncated file and a whole file of another device each look different to the
// checks; each must leave an empty cache, say why once, keep validation silent, and be replaced by
// a usable file when the context goes.
TEST_F(PipelineCacheDeviceTest, AnUnusableFileIsIgnoredAndReplaced) {
  const hsdftest::ScopedTempPath folder("pipeline_cache_unusable");
  const std::filesystem::path file = folder.path() / "pipelines.cache";
  auto maker = open(file);
  ASSERT_NE(maker, nullptr);
  compileOne(*maker);
  EXPECT_EQ(close(maker), 0u);
  const auto whole = readBinaryFile(file);
  ASSERT_TRUE(whole.ok());
  std::vector<std::uint8_t> otherDevice(whole->begin(), whole->end() - 24);
  otherDevice[8] ^= 0xff;  // the vendor: a cache of another GPU, sealed whole
  const std::vector<std::vector<std::uint8_t>> unusable = {
      std::vector<std::uint8_t>(300, 0x5a),
      std::vector<std::uint8_t>(whole->begin(), whole->begin() + std::ptrdiff_t(whole->size() / 2)),
      sealPipelineCacheData(otherDevice)};
  for (const std::vector<std::uint8_t>& bytes : unusable) {
    ASSERT_TRUE(writeBinaryFile(file, bytes).ok());
    const hsdftest::LogCapture warnings;
    auto context = open(file);
    ASSERT_NE(context, nullptr);
    EXPECT_EQ(context->pipelineCache().loadedBytes(), 0u);
    EXPECT_EQ(warnings.count("ignored"), 1u);
    compileOne(*context);
    const std::vector<std::uint8_t> before = driverBytes(file, *context);
    EXPECT_TRUE(before.empty()) << "the test's file should be unusable";
    EXPECT_EQ(close(context), 0u);
    auto reader = open(file);
    ASSERT_NE(reader, nullptr);
    EXPECT_GT(reader->pipelineCache().loadedBytes(), 0u) << "the unusable file was not replaced";
    EXPECT_EQ(close(reader), 0u);
  }
}

}  // namespace
}  // namespace engine::gpu
