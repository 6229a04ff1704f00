// The frame's one release path (engine/render/render_feature.h FrameContext::retire, the renderer's
// gpu::DeferredRelease): an object retired at frame L stays alive while frame L + framesInFlight - 1
// may still run and is destroyed when frame L + framesInFlight is prepared, never later and never
// with a wait for the device. Validation is on: a buffer destroyed while a submitted frame still
// uses it is a message, which fails the test (GpuTest::TearDown).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/gpu/buffer.h"
#include "engine/render/components.h"
#include "engine/render/mesh_feature.h"
#include "engine/scene/transform.h"
#include "gpu_test_support.h"

namespace gputest {
namespace {

using namespace engine;

constexpr std::uint32_t kWidth = 96, kHeight = 64;

// A GPU buffer that notes when it is destroyed: in `destroyedBefore`, the frame number the probe
// feature prepares next (the renderer collects before it prepares a frame).
struct TrackedBuffer {
  gpu::Buffer buffer;
  std::uint64_t retiredAt = 0;
  std::map<std::uint64_t, std::uint64_t>* destroyedBefore = nullptr;  // retiredAt -> frame
  const std::uint64_t* nextPrepared = nullptr;
  TrackedBuffer(gpu::Buffer b, std::uint64_t at, std::map<std::uint64_t, std::uint64_t>* log, const std::uint64_t* next)
      : buffer(std::move(b)), retiredAt(at), destroyedBefore(log), nextPrepared(next) {}
  TrackedBuffer(const TrackedBuffer&) = delete;
  TrackedBuffer& operator=(const TrackedBuffer&) = delete;
  ~TrackedBuffer() { (*destroyedBefore)[retiredAt] = *nextPrepared; }
};

// Each frame: a new buffer, written by the frame's commands (many ordered fills, so the GPU is
// still at it when the CPU moves on), then retired at once with the frame.
class ReleaseProbe final : public render::RenderFeature {
 public:
  std::string_view name() const override { return "release probe"; }
  Status initialize(const gpu::Context& context, const render::RendererFormats&, std::uint32_t) override {
    context_ = &context;
    return {};
  }
  void prepare(render::FrameContext& frame) override {
    prepared_.push_back(frame.frameNumber);
    gpu::Buffer buffer(*context_, 1 << 20, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly, "probe");
    for (std::uint32_t i = 0; i < 16; ++i) {
      if (i > 0)  // all transfer stages: validation layers that file a fill under "copy" see the order too
        gpu::memoryBarrier(frame.cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
      vkCmdFillBuffer(frame.cmd, buffer.handle(), 0, VK_WHOLE_SIZE, i);
    }
    auto tracked = std::make_unique<TrackedBuffer>(std::move(buffer), frame.frameNumber, &destroyedBefore_, &nextPrepared_);
    frame.retire(std::move(tracked));
    nextPrepared_ = frame.frameNumber + 1;  // what goes from here on goes at a later frame's collect
  }
  void recordPass(render::PassContext&) override {}

  std::map<std::uint64_t, std::uint64_t> destroyedBefore_;
  std::vector<std::uint64_t> prepared_;

 private:
  const gpu::Context* context_ = nullptr;
  std::uint64_t nextPrepared_ = 0;
};

render::CameraView frontCamera() {
  return render::CameraView::lookAt({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 0.8f, 0.1f, float(kWidth) / float(kHeight));
}

class FrameReleaseTest : public GpuTest {
 protected:
  void createRendererWith(std::uint32_t framesInFlight) {
    render::RendererDesc desc;
    desc.framesInFlight = framesInFlight;
    renderer_ = std::make_unique<render::Renderer>(*context_, desc, VkExtent2D{kWidth, kHeight});
    const Status added = renderer_->addFeature(std::make_unique<render::MeshFeature>(*pool_));
    ASSERT_TRUE(added.ok()) << added.error().message;
  }
};

// Tricky: the boundary is exact and depends on the frames in flight: with one frame in flight the
// object goes at the very next frame, with three it must survive two more frames whose CPU work
// overlaps its frame's GPU work. A rule one frame early destroys a buffer a submitted frame still
// fills (a validation message); one frame late, or a collect only at the end of the frame, shows
// in the frame the object went at; and the list must hold no more than the frames in flight.
TEST_F(FrameReleaseTest, RetiredAtFrameLGoesWhenFrameLPlusFramesInFlightIsPrepared) {
  for (const std::uint32_t inFlight : {1u, 2u, 3u}) {
    SCOPED_TRACE("frames in flight " + std::to_string(inFlight));
    createRendererWith(inFlight);
    auto probe = std::make_unique<ReleaseProbe>();
    ReleaseProbe* p = probe.get();
    ASSERT_TRUE(renderer_->addFeature(std::move(probe)).ok());
    constexpr std::uint64_t kFrames = 12;
    for (std::uint64_t f = 0; f < kFrames; ++f) {
      ASSERT_TRUE(renderer_->renderFrame(registry_, frontCamera()));
      EXPECT_EQ(renderer_->pendingReleases(), std::min<std::uint64_t>(f + 1, inFlight)) << "after frame " << f;
    }
    ASSERT_EQ(p->prepared_.size(), kFrames);
    for (std::uint64_t retired = 0; retired + inFlight < kFrames; ++retired) {
      const auto it = p->destroyedBefore_.find(retired);
      ASSERT_NE(it, p->destroyedBefore_.end()) << "the object of frame " << retired << " was never destroyed";
      EXPECT_EQ(it->second, retired + inFlight) << "the object of frame " << retired;
    }
    for (std::uint64_t retired = kFrames - inFlight; retired < kFrames; ++retired)
      EXPECT_FALSE(p->destroyedBefore_.contains(retired)) << "frame " << retired << " may still run";
    renderer_->finish();  // the device is idle: everything goes
    EXPECT_EQ(renderer_->pendingReleases(), 0u);
    EXPECT_EQ(p->destroyedBefore_.size(), kFrames);
    renderer_.reset();
  }
}

// Tricky: the mesh pool uploads all its meshes again whenever one is added, so a mesh added every
// frame replaces the buffers the frames in flight draw from, every frame. They must wait in the
// frame's list for exactly the frames in flight (two buffers a frame, two frames: four), neither
// destroyed at once (today's upload waits for its own submission, which on one queue happens to
// follow the frames in flight: a pool that leaned on that would break with an asynchronous
// upload) nor kept; every quad must still be drawn at the end, from the last upload.
TEST_F(FrameReleaseTest, MeshesAddedEveryFrameReplaceTheBuffersInFlight) {
  createRendererWith(2);
  const std::vector<glm::vec3> normals(4, glm::vec3(0.0f, 0.0f, 1.0f));
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  constexpr int kQuads = 8;
  std::vector<glm::vec3> centers;
  for (int i = 0; i < kQuads; ++i) {
    const glm::vec3 c(-1.4f + 0.4f * float(i), 0.0f, 0.0f);
    centers.push_back(c);
    const std::vector<glm::vec3> positions = {c + glm::vec3(-0.15f, -0.15f, 0.0f), c + glm::vec3(0.15f, -0.15f, 0.0f),
                                              c + glm::vec3(0.15f, 0.15f, 0.0f), c + glm::vec3(-0.15f, 0.15f, 0.0f)};
    const ecs::Entity entity = registry_.create();
    registry_.emplace<scene::Transform>(entity, scene::Transform{});
    render::MeshRenderable renderable;
    renderable.mesh = pool_->add(positions, normals, indices);
    registry_.emplace<render::MeshRenderable>(entity, renderable);
    scene::updateWorldTransforms(registry_);
    ASSERT_TRUE(renderer_->renderFrame(registry_, frontCamera()));
    // Frame 0 makes the first buffers; each later frame retires the two it replaced.
    EXPECT_EQ(renderer_->pendingReleases(), std::size_t(std::min(2 * i, 4))) << "after frame " << i;
  }
  const std::vector<float> depth = renderer_->readbackDepth();
  const render::CameraView camera = frontCamera();
  for (const glm::vec3& c : centers) {
    const glm::vec4 clip = camera.proj * camera.view * glm::vec4(c, 1.0f);
    const auto x = std::uint32_t((clip.x / clip.w * 0.5f + 0.5f) * float(kWidth));
    const auto y = std::uint32_t((clip.y / clip.w * 0.5f + 0.5f) * float(kHeight));
    EXPECT_GT(depth[std::size_t(y) * kWidth + x], 0.0f) << "the quad at x = " << c.x << " is not drawn";
  }
  EXPECT_EQ(depth[std::size_t(kHeight / 2) * kWidth + 0], 0.0f) << "background";
}

}  // namespace
}  // namespace gputest
