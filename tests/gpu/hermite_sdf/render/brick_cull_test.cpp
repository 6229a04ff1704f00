// The brick and cell culling passes (render/brick_culler.h, brick_cull.comp, cell_cull.comp) on the
// test device, validation on. Bricks:
// for a baked sphere and an inside-out sphere (negative on its grid boundary: cone culling must be
// off), under several cameras (outside the frustum, near plane in the grid, eye in the grid, far,
// sheared model), the GPU keeps exactly the bricks its C++ twin (normal_cone.h) keeps, writes them
// into each object's output range and counts them in each object's indirect draw command.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>

#include "cells/cell_bricks.h"
#include "engine/platform/camera_controller.h"
#include "engine/gpu/buffer.h"
#include "gpu_test_support.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/normal_cone.h"
#include "hermite_sdf/render/renderable.h"
#include "render/brick_culler.h"

namespace hsdf {
namespace {

using engine::gpu::Buffer;
using engine::gpu::MemoryUsage;

std::shared_ptr<const SdfAsset> sphereAsset(bool insideOut) {
  const SphereSource sphere({0.05, 0.0, -0.03}, 1.0);
  GridSpec grid;
  grid.resolution = 48;
  grid.spacing = 2.8 / 47.0;
  grid.origin = glm::dvec3(-1.4);
  auto field = bakeHermiteField(sphere, grid);
  EXPECT_TRUE(field.ok());
  if (insideOut)
    for (HermiteSample& s : field->samples) s = {-s.f, -s.fx, -s.fy, -s.fz};
  auto asset = makeSdfAsset(insideOut ? "inside-out sphere" : "sphere", std::move(field.value()), sphere.bounds());
  EXPECT_TRUE(asset.ok());
  return asset.value();
}

struct ObjectInput {
  std::shared_ptr<const SdfAsset> asset;
  CellBricks bricks;
  std::vector<shader::CellBrickCone> cones;
  glm::mat4 model{1.0f};
};

bool sameBrick(const shader::CellBrickGpu& a, const shader::CellBrickGpu& b) {
  return a.xyz == b.xyz && a.firstIndex == b.firstIndex && a.maskLo == b.maskLo && a.maskHi == b.maskHi;
}

class BrickCullTest : public ::testing::Test {
 protected:
  void SetUp() override {
    context_ = gputest::createTestContext(/*synchronizationValidation=*/true);  // checks record()'s barriers
    ASSERT_TRUE(context_);
  }
  void TearDown() override {
    if (!context_) return;
    const auto messages = context_->validationMessages();
    EXPECT_EQ(context_->validationMessageCount(), 0u) << (messages.empty() ? "" : messages.front());
  }
  Buffer hostBuffer(std::size_t bytes, VkBufferUsageFlags usage, const char* name) {
    return Buffer(*context_, std::max<std::size_t>(bytes, 16), usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                  MemoryUsage::Upload, name);
  }
  std::unique_ptr<engine::gpu::Context> context_;
};

// Per camera: cull on the GPU, then compare each object's output range, draw command and the
// totals with the C++ twin. Returns the twin's verdict counts over both objects, per object.
struct TwinCounts {
  std::uint32_t kept = 0, frustum = 0, cone = 0;
};

TEST_F(BrickCullTest, GpuKeepsExactlyTheBricksOfTheCppTwin) {
  auto culler = BrickCuller::create(*context_);
  ASSERT_TRUE(culler.ok()) << culler.error().message;
  std::vector<ObjectInput> objects(2);
  objects[0].asset = sphereAsset(false);
  objects[1].asset = sphereAsset(true);
  ASSERT_TRUE(objects[0].asset->boundaryPositive);
  ASSERT_FALSE(objects[1].asset->boundaryPositive);
  objects[1].model = glm::translate(glm::mat4(1.0f), glm::vec3(3.5f, 0.0f, 0.0f));
  objects[1].model[1][0] = 0.25f;  // shear
  std::vector<shader::CellBrickGpu> allBricks;
  std::vector<shader::CellBrickCone> allCones;
  std::vector<std::uint32_t> firstBrick;
  std::uint32_t maxBricks = 0;
  for (ObjectInput& o : objects) {
    o.bricks = buildCellBricks(o.asset->cells).value();
    auto cones = brickGradientCones(o.asset->cells, o.bricks.bricks, o.bricks.cellRecords);
    ASSERT_TRUE(cones.ok()) << cones.error().message;
    o.cones = std::move(cones.value());
    firstBrick.push_back(std::uint32_t(allBricks.size()));
    allBricks.insert(allBricks.end(), o.bricks.bricks.begin(), o.bricks.bricks.end());
    allCones.insert(allCones.end(), o.cones.begin(), o.cones.end());
    maxBricks = std::max(maxBricks, std::uint32_t(o.bricks.bricks.size()));
  }
  const auto storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  Buffer bricks = hostBuffer(allBricks.size() * sizeof(shader::CellBrickGpu), storage, "bricks");
  Buffer cones = hostBuffer(allCones.size() * sizeof(shader::CellBrickCone), storage, "cones");
  bricks.write(std::span<const shader::CellBrickGpu>(allBricks));
  cones.write(std::span<const shader::CellBrickCone>(allCones));
  Buffer kept = hostBuffer(allBricks.size() * sizeof(shader::CellBrickGpu), storage | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                           "kept bricks");
  Buffer commands = hostBuffer(objects.size() * sizeof(VkDrawIndirectCommand),
                               storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, "commands");
  Buffer cullObjects = hostBuffer(objects.size() * sizeof(shader::BrickCullObject), storage, "cull objects");
  Buffer totals = hostBuffer(sizeof(shader::BrickCullTotals), storage, "totals");

  const glm::vec3 centre(0.05f, 0.0f, -0.03f);
  struct Shot {
    const char* label;
    glm::vec3 eye, target;
    float znear;
  };
  const Shot shots[] = {
      {"both objects in view", {1.8f, 1.2f, 6.0f}, {1.7f, 0.0f, 0.0f}, 0.05f},
      {"sphere half out of the frustum", {0.0f, 0.3f, 4.0f}, {1.6f, 0.3f, 0.0f}, 0.05f},
      {"looking away", {0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 9.0f}, 0.05f},
      {"near plane reaching into the grid", {0.0f, 0.0f, 1.45f}, centre, 0.1f},
      {"eye inside the grid", {0.2f, 0.3f, 1.2f}, centre, 0.01f},
      {"far away", {-40.0f, 25.0f, 60.0f}, centre, 0.5f},
      {"close, oblique", {-1.9f, -1.1f, 1.7f}, {0.4f, 0.2f, 0.0f}, 0.02f},
  };
  std::vector<TwinCounts> overall(objects.size());
  for (const Shot& shot : shots) {
    SCOPED_TRACE(shot.label);
    const auto camera = engine::render::CameraView::lookAt(shot.eye, shot.target, 0.9f, shot.znear, 1.5f);
    std::vector<shader::BrickCullObject> cull;
    std::vector<VkDrawIndirectCommand> draws;
    for (std::uint32_t i = 0; i < objects.size(); ++i) {
      const BrickCuller::ObjectBricks ob{firstBrick[i], std::uint32_t(objects[i].bricks.bricks.size()), firstBrick[i], i};
      cull.push_back(BrickCuller::cullObject(camera, objects[i].model, objects[i].asset->cells.grid,
                                             objects[i].asset->boundaryPositive, ob));
      draws.push_back({18, 0, 0, firstBrick[i]});
    }
    EXPECT_EQ(cull[1].eyeConeTest.w, 0.0f);  // negative boundary: never cone-culled
    cullObjects.write(std::span<const shader::BrickCullObject>(cull));
    commands.write(std::span<const VkDrawIndirectCommand>(draws));
    const shader::BrickCullTotals zero{};
    totals.write(&zero, sizeof(zero));
    const BrickCuller::Buffers addresses{cullObjects.address(), bricks.address(),   cones.address(),
                                         kept.address(),        commands.address(), totals.address()};
    context_->submitAndWait(
        [&](VkCommandBuffer cmd) { culler->record(cmd, addresses, std::uint32_t(objects.size()), maxBricks); });

    std::vector<VkDrawIndirectCommand> gpuDraws(objects.size());
    std::memcpy(gpuDraws.data(), commands.mapped(), gpuDraws.size() * sizeof(VkDrawIndirectCommand));
    const auto* keptBricks = static_cast<const shader::CellBrickGpu*>(kept.mapped());
    shader::BrickCullTotals gpuTotals;
    std::memcpy(&gpuTotals, totals.mapped(), sizeof(gpuTotals));
    TwinCounts sum;
    for (std::uint32_t i = 0; i < objects.size(); ++i) {
      const ObjectInput& o = objects[i];
      const shader::BrickCullObject& co = cull[i];
      std::vector<shader::CellBrickGpu> expected;
      for (std::size_t b = 0; b < o.bricks.bricks.size(); ++b) {
        const BrickBox box = brickBox(o.bricks.bricks[b].xyz, glm::vec3(co.gridOriginSpacing), co.gridOriginSpacing.w);
        const BrickVerdict v = brickVerdict(co.objectToClip, box, o.cones[b], glm::vec3(co.eyeConeTest),
                                            co.eyeConeTest.w != 0.0f);
        if (v == BrickVerdict::Kept) expected.push_back(o.bricks.bricks[b]);
        (v == BrickVerdict::Kept ? overall[i].kept : v == BrickVerdict::FrustumCulled ? overall[i].frustum : overall[i].cone)++;
        (v == BrickVerdict::Kept ? sum.kept : v == BrickVerdict::FrustumCulled ? sum.frustum : sum.cone)++;
      }
      EXPECT_EQ(gpuDraws[i].vertexCount, 18u);
      EXPECT_EQ(gpuDraws[i].firstInstance, firstBrick[i]);
      ASSERT_EQ(gpuDraws[i].instanceCount, expected.size()) << "object " << i;
      std::vector<shader::CellBrickGpu> got(keptBricks + firstBrick[i], keptBricks + firstBrick[i] + expected.size());
      const auto byXyz = [](const shader::CellBrickGpu& a, const shader::CellBrickGpu& b) { return a.xyz < b.xyz; };
      std::sort(got.begin(), got.end(), byXyz);
      std::sort(expected.begin(), expected.end(), byXyz);
      for (std::size_t k = 0; k < expected.size(); ++k) ASSERT_TRUE(sameBrick(got[k], expected[k])) << "object " << i;
    }
    EXPECT_EQ(gpuTotals.tested, std::uint32_t(allBricks.size()));
    EXPECT_EQ(gpuTotals.kept, sum.kept);
    EXPECT_EQ(gpuTotals.frustumCulled, sum.frustum);
    EXPECT_EQ(gpuTotals.coneCulled, sum.cone);
  }
  // Every branch was exercised: the sphere lost bricks to both tests and kept some; the inside-out
  // sphere lost none to its cone.
  EXPECT_GT(overall[0].cone, 0u);
  EXPECT_GT(overall[0].frustum, 0u);
  EXPECT_GT(overall[0].kept, 0u);
  EXPECT_EQ(overall[1].cone, 0u);
  EXPECT_GT(overall[1].kept, 0u);
}

// The cell culling pass (CellCuller, cell_cull.comp) on the same two spheres and cameras, fp32 and
// fp16 records: each range (lengths around the workgroup's 64, so the prefix sum crosses chunks,
// short ones that share a workgroup, and long ones walked in many chunks) must hold exactly the
// cells the C++ twin keeps (brickVerdict on cellBox with cellGradientCone), in the range's order and
// together (one claim per range: its command's firstInstance), each a byte copy of its record
// beside its record and range index; the claims must not overlap, and the append cursor must end
// at the cells kept. Twice per view: streams that hold every cell, then streams that hold a third
// of the kept cells, where a range whose claim does not fit draws nothing from them, its fallback
// command gets its whole row, and the slots it reached are marked as holes for the tiling.
// Synchronization validation checks the barriers.
TEST_F(BrickCullTest, GpuKeepsExactlyTheCellsOfTheCppTwinInOrder) {
  auto culler = CellCuller::create(*context_);
  ASSERT_TRUE(culler.ok()) << culler.error().message;
  std::vector<ObjectInput> objects(2);
  objects[0].asset = sphereAsset(false);
  objects[1].asset = sphereAsset(true);
  objects[1].model = glm::translate(glm::mat4(1.0f), glm::vec3(3.5f, 0.0f, 0.0f));
  objects[1].model[1][0] = 0.25f;  // shear
  // Every record of both objects, their cones, and ranges of 1, 63, 64, 65, 150, 7 and 1000 records.
  std::vector<CellRecord> full;
  std::vector<CellRecordHalf> half;
  std::vector<shader::CellBrickCone> cones;
  std::vector<shader::CellCullRange> ranges;
  const std::uint32_t lengths[] = {1, 63, 64, 65, 150, 7, 1000};
  constexpr std::size_t kLengths = std::size(lengths);
  for (std::uint32_t i = 0; i < objects.size(); ++i) {
    const SdfAsset& a = *objects[i].asset;
    const auto first = std::uint32_t(full.size());
    const auto count = std::uint32_t(a.cells.records.size());
    for (std::uint32_t start = 0, n = 0; start < count; start += lengths[n % kLengths], ++n) {
      const std::uint32_t length = std::min(lengths[n % kLengths], count - start);
      ranges.push_back({first + start, length, 0, std::uint32_t(ranges.size()), i, 0, 0, 0});
    }
    full.insert(full.end(), a.cells.records.begin(), a.cells.records.end());
    half.insert(half.end(), a.cellsHalf.records.begin(), a.cellsHalf.records.end());
    for (const CellRecord& r : a.cells.records) cones.push_back(cellGradientCone(r, a.cells.grid.spacing));
  }
  // Each range's fallback command follows the range commands.
  const auto rangeCount = std::uint32_t(ranges.size());
  for (shader::CellCullRange& range : ranges) range.fallbackCommand = rangeCount + range.drawCommand;
  ASSERT_TRUE(std::any_of(ranges.begin(), ranges.end(), [](const auto& r) { return r.cellCount == 1000; }));
  const auto storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  Buffer records[2] = {hostBuffer(full.size() * sizeof(CellRecord), storage, "records fp32"),
                       hostBuffer(half.size() * sizeof(CellRecordHalf), storage, "records fp16")};
  records[0].write(std::span<const CellRecord>(full));
  records[1].write(std::span<const CellRecordHalf>(half));
  Buffer coneBuffer = hostBuffer(cones.size() * sizeof(shader::CellBrickCone), storage, "cones");
  coneBuffer.write(std::span<const shader::CellBrickCone>(cones));
  // The ranges as the feature uploads them: packs of short ranges (1 + 63, 7 + 1 + ...) share a
  // workgroup, 64, 65, 150 and 1000 are walked alone.
  const CellCuller::RangeUpload upload = CellCuller::rangeUpload(ranges);
  EXPECT_LT(upload.packCount, ranges.size());
  Buffer rangeBuffer = hostBuffer(upload.words.size() * sizeof(std::uint32_t), storage, "ranges");
  rangeBuffer.write(std::span<const std::uint32_t>(upload.words));
  Buffer kept = hostBuffer(full.size() * sizeof(CellRecord), storage | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "kept");
  Buffer indices = hostBuffer(full.size() * sizeof(std::uint32_t), storage, "kept indices");
  Buffer keptRanges = hostBuffer(full.size() * sizeof(std::uint32_t), storage, "kept ranges");
  Buffer commands = hostBuffer(2 * ranges.size() * sizeof(VkDrawIndirectCommand),
                               storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, "commands");
  Buffer cullObjects = hostBuffer(objects.size() * sizeof(shader::BrickCullObject), storage, "cull objects");
  Buffer totals = hostBuffer(sizeof(shader::BrickCullTotals), storage, "totals");

  const glm::vec3 centre(0.05f, 0.0f, -0.03f);
  const std::pair<glm::vec3, glm::vec3> shots[] = {{{1.8f, 1.2f, 6.0f}, {1.7f, 0.0f, 0.0f}},
                                                   {{0.0f, 0.3f, 4.0f}, {1.6f, 0.3f, 0.0f}},
                                                   {{0.2f, 0.3f, 1.2f}, centre},
                                                   {{-1.9f, -1.1f, 1.7f}, {0.4f, 0.2f, 0.0f}}};
  constexpr std::uint32_t kUnwritten = 0xaaaaaaaau, kHole = ~0u;
  TwinCounts overall;
  std::uint32_t fellBack = 0, fitted = 0;
  for (int precision = 0; precision < 2; ++precision) {
    const std::uint32_t recordBytes = precision == 0 ? sizeof(CellRecord) : sizeof(CellRecordHalf);
    const auto* source = static_cast<const std::uint8_t*>(records[precision].mapped());
    for (const auto& [eye, target] : shots) {
      const auto camera = engine::render::CameraView::lookAt(eye, target, 0.9f, 0.02f, 1.5f);
      std::vector<shader::BrickCullObject> cull;
      for (const ObjectInput& o : objects)
        cull.push_back(BrickCuller::cullObject(camera, o.model, o.asset->cells.grid, o.asset->boundaryPositive, {}));
      cullObjects.write(std::span<const shader::BrickCullObject>(cull));
      // What the C++ twin keeps, range by range.
      TwinCounts sum;
      std::vector<std::vector<std::uint32_t>> expected(ranges.size());
      for (const shader::CellCullRange& range : ranges) {
        const shader::BrickCullObject& co = cull[range.object];
        for (std::uint32_t r = range.firstCell; r < range.firstCell + range.cellCount; ++r) {
          const BrickBox box = cellBox({full[r].x, full[r].y, full[r].z}, glm::vec3(co.gridOriginSpacing),
                                       co.gridOriginSpacing.w);
          const BrickVerdict v =
              brickVerdict(co.objectToClip, box, cones[r], glm::vec3(co.eyeConeTest), co.eyeConeTest.w != 0.0f);
          if (v == BrickVerdict::Kept) expected[range.drawCommand].push_back(r);
          (v == BrickVerdict::Kept ? sum.kept : v == BrickVerdict::FrustumCulled ? sum.frustum : sum.cone)++;
          if (range.object == 1) {
            ASSERT_NE(v, BrickVerdict::ConeCulled) << "negative boundary: never cone-culled";
          }
        }
      }
      for (const std::uint32_t capacity : {std::uint32_t(full.size()), sum.kept / 3}) {
        SCOPED_TRACE(std::string(precision == 0 ? "fp32" : "fp16") + ", eye " + std::to_string(eye.x) +
                     ", streams of " + std::to_string(capacity) + " slots");
        std::vector<VkDrawIndirectCommand> initial(ranges.size(), VkDrawIndirectCommand{8, 0, 0, 0});
        for (const shader::CellCullRange& range : ranges) initial.push_back({8, 0, 0, range.firstCell});
        commands.write(std::span<const VkDrawIndirectCommand>(initial));
        const shader::BrickCullTotals zero{};
        totals.write(&zero, sizeof(zero));
        std::fill_n(static_cast<std::uint32_t*>(keptRanges.mapped()), full.size(), kUnwritten);
        shader::CellCullPushConstants push{};
        push.objects = cullObjects.address();
        push.ranges = rangeBuffer.address();
        push.records = records[precision].address();
        push.cones = coneBuffer.address();
        push.keptRecords = kept.address();
        push.keptIndices = indices.address();
        push.keptRanges = keptRanges.address();
        push.commands = commands.address();
        push.totals = totals.address();
        push.rangeCount = rangeCount;
        push.recordWords = recordBytes / 4;
        push.recordPrecision = std::uint32_t(precision);
        push.keptCapacity = capacity;
        push.packCount = upload.packCount;
        context_->submitAndWait([&](VkCommandBuffer cmd) {
          barrierBeforeCulling(cmd);
          culler->record(cmd, push);
          barrierAfterCulling(cmd);
        });
        const auto* gpuCommands = static_cast<const VkDrawIndirectCommand*>(commands.mapped());
        const auto* gpuIndices = static_cast<const std::uint32_t*>(indices.mapped());
        const auto* gpuRanges = static_cast<const std::uint32_t*>(keptRanges.mapped());
        const auto* gpuKept = static_cast<const std::uint8_t*>(kept.mapped());
        shader::BrickCullTotals gpuTotals;
        std::memcpy(&gpuTotals, totals.mapped(), sizeof(gpuTotals));
        ASSERT_EQ(gpuTotals.keptSlots[precision], sum.kept) << "the cursor is not the cells kept";
        EXPECT_EQ(gpuTotals.keptSlots[1 - precision], 0u);
        std::vector<std::uint32_t> owner(capacity, kHole);  // the fitting range of each slot
        std::uint32_t fallbackCells = 0;
        for (const shader::CellCullRange& range : ranges) {
          const std::vector<std::uint32_t>& want = expected[range.drawCommand];
          const VkDrawIndirectCommand& command = gpuCommands[range.drawCommand];
          const VkDrawIndirectCommand& fallback = gpuCommands[range.fallbackCommand];
          EXPECT_EQ(command.vertexCount, 8u);
          EXPECT_EQ(fallback.firstInstance, range.firstCell) << "the fallback draws the row from the record buffer";
          if (!want.empty() && command.instanceCount == 0) {  // the claim did not fit
            ASSERT_LT(capacity, sum.kept) << "range " << range.drawCommand << " fell back from streams that hold every cell";
            ASSERT_EQ(fallback.instanceCount, range.cellCount) << "range " << range.drawCommand;
            fallbackCells += range.cellCount;
            fellBack++;
            continue;
          }
          ASSERT_EQ(fallback.instanceCount, 0u) << "range " << range.drawCommand << " fell back though it fits";
          ASSERT_EQ(command.instanceCount, want.size()) << "range " << range.drawCommand;
          if (want.empty()) continue;
          fitted++;
          ASSERT_LE(std::uint64_t(command.firstInstance) + want.size(), capacity) << "range " << range.drawCommand;
          for (std::size_t k = 0; k < want.size(); ++k) {
            const std::uint32_t slot = command.firstInstance + std::uint32_t(k);
            ASSERT_EQ(owner[slot], kHole) << "slot " << slot << " claimed by ranges " << owner[slot] << " and "
                                          << range.drawCommand;
            owner[slot] = range.drawCommand;
            ASSERT_EQ(gpuIndices[slot], want[k]) << "range " << range.drawCommand << ", kept cell " << k;
            ASSERT_EQ(gpuRanges[slot], range.drawCommand) << "range " << range.drawCommand << ", kept cell " << k;
            ASSERT_EQ(std::memcmp(gpuKept + std::size_t(slot) * recordBytes,
                                  source + std::size_t(want[k]) * recordBytes, recordBytes),
                      0)
                << "the kept record is not a copy of record " << want[k];
          }
        }
        // Below the cursor every slot belongs to a fitting range or is a marked hole.
        for (std::uint32_t slot = 0; slot < std::min(capacity, sum.kept); ++slot) {
          if (owner[slot] == kHole) {
            ASSERT_EQ(gpuRanges[slot], kHole) << "slot " << slot << " is neither claimed by a fitting range nor a hole";
          }
        }
        EXPECT_EQ(gpuTotals.fallbackCells, fallbackCells);
        EXPECT_EQ(gpuTotals.tested, std::uint32_t(full.size()));
        EXPECT_EQ(gpuTotals.kept, sum.kept);
        EXPECT_EQ(gpuTotals.frustumCulled, sum.frustum);
        EXPECT_EQ(gpuTotals.coneCulled, sum.cone);
      }
      overall.kept += sum.kept;
      overall.frustum += sum.frustum;
      overall.cone += sum.cone;
    }
  }
  EXPECT_GT(fellBack, 0u) << "no range fell back from streams that hold a third of the kept cells";
  EXPECT_GT(fitted, fellBack);
  // Every branch was exercised: cells kept, removed by the frustum and by the cones.
  EXPECT_GT(overall.kept, 0u);
  EXPECT_GT(overall.frustum, 0u);
  EXPECT_GT(overall.cone, 0u);
}

// The measurement of docs/perf/cells-breakdown-lavapipe.md ("Brick culling"), on the C++ twin (no
// device): the bunny baked by the module's bake job (padding 1) at K = 16..128, 4x4x4 bricks, the
// perf capture's 8 orbit views (Viewer: framingOrbit on the source's bounds, fovY 0.8, znear 1 % of
// the bounds' diagonal, 1920x1080). Prints the share of bricks the frustum and the cone remove. It
// asserts what holds for any correct culling: the bunny's boundary is positive, the cone test is
// allowed from every orbit view and removes bricks at every K.
TEST(BunnyBrickCull, ShareOfBricksRemovedOnTheCaptureViews) {
  auto source = BakeSource::fromPathOrShape(gputest::sampleAsset("bunny.glb").string());
  ASSERT_TRUE(source.ok()) << source.error().message;
  auto prepared = prepareSource(*source, BakeSettings{});
  ASSERT_TRUE(prepared.ok()) << prepared.error().message;
  std::printf("K    cells   bricks  cells/brick  kept%%  frustum%%  cone%%  (mean of 8 views)\n");
  for (const int k : {16, 32, 64, 128}) {
    BakeSettings settings;
    settings.resolution = k;
    settings.band = BakeBand::Sparse;
    auto asset = bakeAsset(*prepared, settings);
    ASSERT_TRUE(asset.ok()) << asset.error().message;
    const SdfAsset& a = *asset.value();
    ASSERT_TRUE(a.boundaryPositive) << k;
    const CellBricks bricks = buildCellBricks(a.cells).value();
    auto conesOr = brickGradientCones(a.cells, bricks.bricks, bricks.cellRecords);
    ASSERT_TRUE(conesOr.ok()) << conesOr.error().message;
    const std::vector<shader::CellBrickCone>& cones = conesOr.value();
    const glm::vec3 lo(a.surfaceBounds.min), hi(a.surfaceBounds.max);
    const float znear = float(0.01 * glm::length(a.surfaceBounds.max - a.surfaceBounds.min));
    double kept = 0, frustum = 0, cone = 0;
    for (int view = 0; view < 8; ++view) {
      const engine::platform::OrbitController orbit = engine::platform::framingOrbit(lo, hi, 0.8f, view);
      const auto camera = engine::render::CameraView::lookAt(orbit.eye(), orbit.target, 0.8f, znear, 1920.0f / 1080.0f);
      const shader::BrickCullObject o = BrickCuller::cullObject(camera, glm::mat4(1.0f), a.cells.grid, true, {});
      ASSERT_EQ(o.eyeConeTest.w, 1.0f) << "K " << k << " view " << view;
      for (std::size_t b = 0; b < bricks.bricks.size(); ++b) {
        const BrickBox box = brickBox(bricks.bricks[b].xyz, glm::vec3(o.gridOriginSpacing), o.gridOriginSpacing.w);
        const BrickVerdict v = brickVerdict(o.objectToClip, box, cones[b], glm::vec3(o.eyeConeTest), true);
        (v == BrickVerdict::Kept ? kept : v == BrickVerdict::FrustumCulled ? frustum : cone) += 1.0;
      }
    }
    EXPECT_GT(cone, 0.0) << "K " << k;
    const double total = 8.0 * double(bricks.bricks.size());
    std::printf("%-4d %-7zu %-7zu %-12.2f %-6.1f %-9.1f %-6.1f\n", k, a.cells.records.size(), bricks.bricks.size(),
                double(a.cells.records.size()) / double(bricks.bricks.size()), 100.0 * kept / total,
                100.0 * frustum / total, 100.0 * cone / total);
  }
}

}  // namespace
}  // namespace hsdf
