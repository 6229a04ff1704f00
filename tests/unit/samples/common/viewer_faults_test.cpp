// Faults the Viewer (samples/common/viewer.h) must survive as clear errors and a clean close, on
// the test device (HSDF_TEST_DEVICE, lavapipe unless set) with the validation layers on: a lost
// device, GPU memory past the allocator's budget, missing or broken shader files. Small images
// (64x48) keep it fast.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "engine/gpu/memory.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/core/bake_job.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/vk_check.h"
#include "test_viewer.h"

namespace samples {
namespace {

struct FaultGuard {  // a failing test must not leave a fault armed for the next one
  ~FaultGuard() { engine::gpu::clearInjectedFaults(); }
};

engine::Expected<std::unique_ptr<Viewer>> createViewer() { return createTestViewer(64, 48); }

std::unique_ptr<Viewer> viewTorus() {
  auto viewer = createViewer();
  EXPECT_TRUE(viewer.ok()) << viewer.error().message;
  if (!viewer.ok()) return nullptr;
  SceneDesc scene;
  scene.shape = "torus";
  scene.groundPlane = false;
  TuningState tuning;
  tuning.resolution = 16;
  const engine::Status loaded = (*viewer)->loadScene(scene, tuning);
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  return loaded.ok() ? std::move(*viewer) : nullptr;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::size_t differingPixels(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::size_t count = 0;
  for (std::size_t i = 0; i + 3 < std::min(a.size(), b.size()); i += 4)
    count += std::equal(a.begin() + i, a.begin() + i + 4, b.begin() + i) ? 0 : 1;
  return count;
}

// A second SDF beside the torus (inside the orbit view), drawn by cells: its own asset, so its
// records must be uploaded on its first frame.
engine::ecs::Entity addSphere(Viewer& viewer, const std::string& name) {
  hsdf::BakeSettings settings;
  settings.resolution = 12;
  hsdf::BakeSource source = hsdf::BakeSource::fromShape("sphere");
  source.name = name;
  auto asset = hsdf::bakeAsset(source, settings);
  EXPECT_TRUE(asset.ok()) << asset.error().message;
  hsdf::HermiteSdfRenderable renderable;
  if (asset.ok()) renderable.asset = std::move(*asset);
  applyTuning(viewer.tuning(), renderable);
  engine::ecs::Registry& registry = viewer.registry();
  const engine::ecs::Entity entity = registry.create();
  engine::scene::Transform transform;
  transform.translation = viewer.boundsMax();
  registry.emplace<engine::scene::Transform>(entity, transform);
  registry.emplace<hsdf::HermiteSdfRenderable>(entity, std::move(renderable));
  return entity;
}

// Tricky: the lost device comes from the frame's own vkQueueSubmit2 (inside the renderer, which
// knows nothing of it); step() must turn it into an error naming the call, later steps must not
// wait on a fence that will never signal, and close() must tear down without throwing from a
// destructor (its vkDeviceWaitIdle reports the loss too) and say the device was lost.
TEST(ViewerFaults, DeviceLostIsAnErrorAndACleanClose) {
  FaultGuard guard;
  auto viewer = viewTorus();
  ASSERT_NE(viewer, nullptr);
  ASSERT_TRUE(viewer->step().ok());
  engine::gpu::injectFault({"vkQueueSubmit2", VK_ERROR_DEVICE_LOST, 0});
  const engine::Status lost = viewer->step();
  ASSERT_FALSE(lost.ok());
  EXPECT_TRUE(contains(lost.error().message, "frame 2: the Vulkan device was lost")) << lost.error().message;
  EXPECT_TRUE(contains(lost.error().message, "vkQueueSubmit2")) << lost.error().message;
  const engine::Status again = viewer->step();
  ASSERT_FALSE(again.ok());
  EXPECT_TRUE(contains(again.error().message, "an earlier frame failed")) << again.error().message;
  const engine::Status closed = viewer->close();
  ASSERT_FALSE(closed.ok());
  EXPECT_TRUE(contains(closed.error().message, "device was lost")) << closed.error().message;
  EXPECT_FALSE(contains(closed.error().message, "validation")) << closed.error().message;
}

// Tricky: the final wait fails with something other than a lost device, and the Viewer is
// destroyed without close(): the destructor closes, and a close() that let this error out of a
// destructor terminated the program. Teardown must go on to the end (nothing left for the layer
// to report at device destruction), the destructor must only log, and an explicit close() must
// return the error naming the call.
TEST(ViewerFaults, FailedFinalWaitIsAnErrorNotATerminate) {
  FaultGuard guard;
  auto destroyed = viewTorus();
  ASSERT_NE(destroyed, nullptr);
  ASSERT_TRUE(destroyed->step().ok());
  engine::gpu::injectFault({"vkDeviceWaitIdle", VK_ERROR_OUT_OF_HOST_MEMORY, 0});
  const std::uint64_t messagesBefore = engine::gpu::Context::processValidationMessageCount();
  destroyed.reset();
  EXPECT_EQ(engine::gpu::Context::processValidationMessageCount(), messagesBefore);

  auto closedExplicitly = viewTorus();
  ASSERT_NE(closedExplicitly, nullptr);
  ASSERT_TRUE(closedExplicitly->step().ok());
  engine::gpu::injectFault({"vkDeviceWaitIdle", VK_ERROR_OUT_OF_HOST_MEMORY, 0});
  const engine::Status closed = closedExplicitly->close();
  ASSERT_FALSE(closed.ok());
  EXPECT_TRUE(contains(closed.error().message, "vkDeviceWaitIdle")) << closed.error().message;
  EXPECT_TRUE(contains(closed.error().message, "VK_ERROR_OUT_OF_HOST_MEMORY")) << closed.error().message;
  EXPECT_FALSE(contains(closed.error().message, "validation")) << closed.error().message;
}

// Tricky: the budget is lowered while the scene runs, to exactly what is in use: the frames keep
// coming until a re-bake at a larger K needs new GPU memory for its cells; that frame must fail
// with the allocator's message (the resource, its size, the budget), not crash, and close() must
// find nothing for the validation layers to complain about.
TEST(ViewerFaults, GpuBudgetLoweredWhileRunningFailsTheUploadByName) {
  auto viewer = viewTorus();
  ASSERT_NE(viewer, nullptr);
  for (int frame = 0; frame < 3; ++frame)  // every frame-in-flight slot has made its buffers
    ASSERT_TRUE(viewer->step().ok());
  engine::gpu::Allocator& allocator = viewer->context().allocator();
  allocator.setBudget(allocator.stats().usedBytes);
  const engine::Status fits = viewer->step();
  ASSERT_TRUE(fits.ok()) << "nothing new to allocate: the frame fits; " << fits.error().message;
  TuningState tuning = viewer->tuning();
  tuning.resolution = 32;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok()) << "the bake is on the CPU: the GPU budget does not stop it";
  const engine::Status failed = viewer->step();
  ASSERT_FALSE(failed.ok());
  EXPECT_TRUE(contains(failed.error().message, "out of GPU memory (GPU memory budget: '")) << failed.error().message;
  EXPECT_TRUE(contains(failed.error().message, "the budget is " + std::to_string(allocator.budget()) + " B"))
      << failed.error().message;
  const engine::Status next = viewer->step();
  EXPECT_TRUE(next.ok()) << "the refused asset is reported once; later frames go on: " << next.error().message;
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

// Tricky: the re-baked field is swapped into the entity before any frame tries to upload it, so
// the frame that finds the GPU refusing it no longer has the old field in the scene. The feature
// must draw the field the entity drew before (it still holds its records or texture) in that very
// frame, and the Viewer must put the old field back, say so, and set the tuning back to the K on
// screen, so that every frame from the refusal on draws the old torus pixel for pixel and the panel
// does not claim K 32. Both drawing features: the cells (records rebuilt into new buffers) and the
// dense Hermite tracer (a texture per asset). The control re-bakes K 32 with the budget lifted:
// that image differs, so "the old field" is seen in the pixels, not assumed.
void expectRebakePastTheBudgetKeepsTheOldField(Method method) {
  auto viewer = viewTorus();
  ASSERT_NE(viewer, nullptr);
  TuningState tuning = viewer->tuning();
  tuning.method = method;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  for (int frame = 0; frame < 3; ++frame) ASSERT_TRUE(viewer->step().ok());
  const std::vector<std::uint8_t> k16 = viewer->renderer().readbackColor();
  engine::gpu::Allocator& allocator = viewer->context().allocator();
  const VkDeviceSize readbackBytes = 64 * 48 * 4;
  allocator.setBudget(allocator.stats().usedBytes + 2 * readbackBytes);
  tuning.resolution = 32;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());

  const engine::Status refused = viewer->step();
  ASSERT_FALSE(refused.ok()) << "the K 32 field must not fit the budget";
  EXPECT_TRUE(contains(refused.error().message, "is not drawn")) << refused.error().message;
  EXPECT_TRUE(contains(refused.error().message, "re-baking at resolution 32: the new field does not fit in GPU "
                                                "memory; resolution 16 stays drawn"))
      << refused.error().message;
  EXPECT_EQ(viewer->tuning().resolution, 16) << "the tuning names the K on screen";
  EXPECT_EQ(differingPixels(viewer->renderer().readbackColor(), k16), 0u)
      << "the frame that found out draws the K 16 field";
  for (int frame = 0; frame < 3; ++frame) {
    const engine::Status next = viewer->step();
    ASSERT_TRUE(next.ok()) << "step " << frame + 1 << " after the refusal: " << next.error().message;
  }
  EXPECT_EQ(differingPixels(viewer->renderer().readbackColor(), k16), 0u) << "the K 16 field is drawn again";

  allocator.setBudget(engine::gpu::Allocator::kUnlimited);
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(viewer->tuning().resolution, 32);
  EXPECT_GT(differingPixels(viewer->renderer().readbackColor(), k16), 0u) << "control: K 32 looks different";
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

TEST(ViewerFaults, RebakePastTheGpuBudgetKeepsDrawingTheOldField) { expectRebakePastTheBudgetKeepsTheOldField(hsdf::RenderMethod::Cells); }

TEST(ViewerFaults, RebakePastTheGpuBudgetKeepsDrawingTheOldTracedField) {
  expectRebakePastTheBudgetKeepsTheOldField(hsdf::RenderMethod::HermiteSphereTrace);
}

// Tricky: the new object's cell records are uploaded by the cell feature inside the frame (in
// prepare(), with the frame's command buffer recording), into buffers that also hold the torus's
// records again, so the allocation that fails would have replaced the buffers the torus draws
// from. Before the fix the exception left the frame half-recorded after its fence was reset, and
// every later step refused ("an earlier frame failed"). Now the frame must draw the torus pixel
// for pixel as before and the sphere not at all, name the dropped object and the budget, not
// report it again, and the next frames must draw. The control (the sphere baked again, a new
// asset, after the budget is lifted) shows the sphere's pixels would have differed, so "not
// drawn" is seen in the image, not assumed.
TEST(ViewerFaults, ObjectPastTheGpuBudgetIsDroppedAndTheRestKeepsDrawing) {
  auto viewer = viewTorus();
  ASSERT_NE(viewer, nullptr);
  for (int frame = 0; frame < 3; ++frame)  // every frame-in-flight slot has made its buffers
    ASSERT_TRUE(viewer->step().ok());
  const std::vector<std::uint8_t> torusOnly = viewer->renderer().readbackColor();
  engine::gpu::Allocator& allocator = viewer->context().allocator();
  // Room for the read-backs' staging buffer (64x48 RGBA8), not for the torus's and the sphere's
  // records together (about 120 KB of fp32 records).
  const VkDeviceSize readbackBytes = 64 * 48 * 4;
  allocator.setBudget(allocator.stats().usedBytes + 2 * readbackBytes);
  const engine::ecs::Entity sphere = addSphere(*viewer, "refused sphere");

  const engine::Status dropped = viewer->step();
  ASSERT_FALSE(dropped.ok()) << "the sphere's upload must not fit the budget";
  EXPECT_TRUE(contains(dropped.error().message, "frame 4: hermite cells: 'refused sphere'")) << dropped.error().message;
  EXPECT_TRUE(contains(dropped.error().message, "is not drawn: out of GPU memory (GPU memory budget: 'hermite cells fp32' needs"))
      << dropped.error().message;
  EXPECT_EQ(differingPixels(viewer->renderer().readbackColor(), torusOnly), 0u)
      << "the frame that dropped the sphere draws the torus as before";
  for (int frame = 0; frame < 3; ++frame) {  // both frame slots, the failed frame's one included
    const engine::Status next = viewer->step();
    ASSERT_TRUE(next.ok()) << "frame " << 5 + frame << ": " << next.error().message;
  }
  EXPECT_EQ(differingPixels(viewer->renderer().readbackColor(), torusOnly), 0u);

  allocator.setBudget(engine::gpu::Allocator::kUnlimited);
  viewer->registry().destroy(sphere);
  addSphere(*viewer, "control sphere");
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_GT(differingPixels(viewer->renderer().readbackColor(), torusOnly), 20u)
      << "control: the sphere, when it fits, is on screen";
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

// Tricky: the failure comes from the renderer itself, after the features recorded everything
// (vkEndCommandBuffer), so no feature can catch it. Before the fix the renderer had reset the
// frame's fence at the start of the frame and never submitted: the next frame on that slot (two
// steps later) would wait forever, which is why the Viewer refused every later step. The steps
// after the failure go past that slot; the colour target must still hold the last finished frame
// (nothing of the failed one ran) and the frames after it must draw the same image.
TEST(ViewerFaults, FrameFailingWhileRecordedIsSkippedAndTheNextFramesDraw) {
  FaultGuard guard;
  auto viewer = viewTorus();
  ASSERT_NE(viewer, nullptr);
  for (int frame = 0; frame < 3; ++frame) ASSERT_TRUE(viewer->step().ok());
  const std::vector<std::uint8_t> drawn = viewer->renderer().readbackColor();
  engine::gpu::injectFault({"vkEndCommandBuffer", VK_ERROR_OUT_OF_DEVICE_MEMORY, 0});
  const engine::Status failed = viewer->step();
  ASSERT_FALSE(failed.ok());
  EXPECT_TRUE(contains(failed.error().message, "frame 4: out of GPU memory (vkEndCommandBuffer"))
      << failed.error().message;
  EXPECT_TRUE(contains(failed.error().message, "the frame was skipped")) << failed.error().message;
  EXPECT_EQ(differingPixels(viewer->renderer().readbackColor(), drawn), 0u);
  for (int frame = 0; frame < 3; ++frame) {
    const engine::Status next = viewer->step();
    ASSERT_TRUE(next.ok()) << "step " << frame + 1 << " after the failed frame: " << next.error().message;
  }
  EXPECT_EQ(differingPixels(viewer->renderer().readbackColor(), drawn), 0u);
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

// A copy of the built shaders, one of them broken by `breakIt`, as HSDF_SHADER_DIR for one test.
class BrokenShaderDir {
 public:
  explicit BrokenShaderDir(const std::string& testName) {
    real_ = engine::gpu::shaderDirectory();
    dir_ = std::filesystem::path(testing::TempDir()) / ("hsdf_shaders_" + testName);
    std::filesystem::remove_all(dir_);
    std::filesystem::copy(real_, dir_, std::filesystem::copy_options::recursive);
    environment_.emplace("HSDF_SHADER_DIR", dir_.string());
  }
  ~BrokenShaderDir() {
    environment_.reset();
    std::filesystem::remove_all(dir_);
  }
  std::filesystem::path file(const std::string& name) const { return dir_ / name; }

 private:
  std::filesystem::path real_;
  std::filesystem::path dir_;
  std::optional<hsdftest::ScopedEnvironment> environment_;
};

void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// Tricky: each breakage reaches a different check: a missing file and a directory in its place
// fail the file read, a 6-byte file the size check, 64 bytes of text the SPIR-V header check
// (without it the bytes would go to the driver, which need not survive them). Every error must name
// the file; creating the viewer must fail, not crash or leave a half-made device behind.
TEST(ViewerFaults, MissingOrBrokenShaderFileIsNamed) {
  const std::string shader = "mesh.vert.spv";  // the mesh feature's: loaded by every viewer
  struct Case {
    const char* name;
    void (*breakIt)(const std::filesystem::path&);
    const char* expected;
  };
  const Case cases[] = {
      {"missing", [](const std::filesystem::path& p) { std::filesystem::remove(p); }, "not a readable file"},
      {"directory",
       [](const std::filesystem::path& p) {
         std::filesystem::remove(p);
         std::filesystem::create_directory(p);
       },
       "not a readable file"},
      {"truncated", [](const std::filesystem::path& p) { writeBytes(p, std::string("\x03\x02\x23\x07\x00\x00", 6)); }, "size 6"},
      {"text", [](const std::filesystem::path& p) { writeBytes(p, std::string(64, 'x')); }, "no SPIR-V header"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    BrokenShaderDir dir(c.name);
    c.breakIt(dir.file(shader));
    const auto viewer = createViewer();
    ASSERT_FALSE(viewer.ok()) << "a viewer was created with a " << c.name << " " << shader;
    EXPECT_TRUE(contains(viewer.error().message, dir.file(shader).string())) << viewer.error().message;
    EXPECT_TRUE(contains(viewer.error().message, c.expected)) << viewer.error().message;
  }
}

}  // namespace
}  // namespace samples
