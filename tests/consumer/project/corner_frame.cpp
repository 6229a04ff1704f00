// A render feature of the consumer's own beside the module's: its shaders compiled by the
// package's hermite_sdf_add_shaders (CMakeLists.txt), its struct in a host/device header of its
// own (shaders/corner_host_device.h), its SPIR-V found through engine::gpu::addShaderDirectory. It
// draws a triangle over the frame's top-left corner in the shading pass and times it. Exit code 0
// only when the corner shows the triangle's colour, the opposite corner the clear colour, the
// renderer reports the feature's timing scope, a reload of its shaders succeeds, and the
// validation layers said nothing.
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "corner_host_device.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/gpu/gpu_timer.h"
#include "engine/gpu/pipeline.h"
#include "engine/render/camera_view.h"
#include "engine/render/render_feature.h"
#include "engine/render/renderer.h"
#include "hermite_sdf/render/features.h"

namespace {

constexpr std::uint32_t kSize = 32;

class CornerFeature final : public engine::render::RenderFeature {
 public:
  std::string_view name() const override { return "corner"; }
  engine::Status initialize(const engine::gpu::Context& context, const engine::render::RendererFormats& formats,
                            std::uint32_t /*framesInFlight*/) override {
    context_ = &context;
    formats_ = formats;
    ENGINE_TRY_ASSIGN(pipeline_, createPipeline());
    return {};
  }
  engine::Status reloadShaders() override {
    ENGINE_TRY_ASSIGN(engine::gpu::Pipeline pipeline, createPipeline());
    pipeline_ = std::move(pipeline);
    return {};
  }
  void prepare(engine::render::FrameContext& /*frame*/) override {}
  void recordPass(engine::render::PassContext& pass) override {
    if (pass.pass != engine::render::Pass::Opaque) return;
    const engine::gpu::GpuTimerScope timed(&pass.timer, pass.cmd, "corner");
    vkCmdBindPipeline(pass.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.handle());
    const shader::CornerPushConstants push{glm::vec4(0.0f, 1.0f, 0.0f, 1.0f)};
    vkCmdPushConstants(pass.cmd, pipeline_.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                       sizeof(push), &push);
    vkCmdDraw(pass.cmd, 3, 1, 0, 0);
  }

 private:
  engine::Expected<engine::gpu::Pipeline> createPipeline() const {
    ENGINE_TRY_ASSIGN(engine::gpu::ShaderModule vert, engine::gpu::ShaderModule::load(*context_, "corner.vert"));
    ENGINE_TRY_ASSIGN(engine::gpu::ShaderModule frag, engine::gpu::ShaderModule::load(*context_, "corner.frag"));
    engine::gpu::GraphicsPipelineDesc desc;
    desc.name = "corner";
    desc.vertex = vert.handle();
    desc.fragment = frag.handle();
    desc.cullMode = VK_CULL_MODE_NONE;
    desc.depthTest = false;
    desc.depthWrite = false;
    desc.colorFormats = {formats_.color};
    desc.depthFormat = formats_.depth;
    desc.pushConstantBytes = sizeof(shader::CornerPushConstants);
    return engine::gpu::Pipeline::createGraphics(*context_, desc);
  }

  const engine::gpu::Context* context_ = nullptr;
  engine::render::RendererFormats formats_;
  engine::gpu::Pipeline pipeline_;
};

int fail(const char* what, const std::string& message) {
  std::fprintf(stderr, "corner_frame: %s: %s\n", what, message.c_str());
  return 1;
}

// One assertion of the program: false (and the reason printed) when `holds` is not.
bool expect(bool holds, const char* what, const std::string& message) {
  if (!holds) fail(what, message);
  return holds;
}

}  // namespace

int main() {
  setenv("HSDF_SHADER_DIR", CONSUMER_SHADER_DIR, 1);  // the package's SPIR-V (torus_frame.cpp says why)
  engine::gpu::addShaderDirectory(CORNER_SHADER_DIR);  // this project's, compiled by hermite_sdf_add_shaders

  engine::gpu::ContextDesc desc;
  desc.applicationName = "hermite_sdf consumer";
  desc.device = engine::gpu::DevicePreference::Auto;
  desc.validation = true;
  auto context = engine::gpu::Context::create(desc);
  if (!context) return fail("vulkan", context.error().message);

  engine::render::Renderer renderer(**context, engine::render::RendererDesc{}, VkExtent2D{kSize, kSize});
  if (auto added = hsdf::addRenderFeatures(renderer); !added) return fail("render features", added.error().message);
  if (auto added = renderer.addFeature(std::make_unique<CornerFeature>()); !added)
    return fail("corner feature", added.error().message);

  const engine::ecs::Registry registry;
  const auto camera = engine::render::CameraView::lookAt({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 0.9f, 0.05f, 1.0f);
  for (int frame = 0; frame < 3; ++frame) renderer.renderFrame(registry, camera);
  renderer.finish();
  const std::vector<std::uint8_t> rgba = renderer.readbackColor();
  const auto pixel = [&](std::uint32_t x, std::uint32_t y) { return &rgba[(std::size_t(y) * kSize + x) * 4]; };
  const std::uint8_t* corner = pixel(2, 2);
  const std::uint8_t* opposite = pixel(kSize - 3, kSize - 3);
  std::printf("corner_frame: corner (%u, %u, %u), opposite (%u, %u, %u)\n", corner[0], corner[1], corner[2],
              opposite[0], opposite[1], opposite[2]);
  bool timed = false;
  for (const engine::gpu::GpuTiming& timing : renderer.lastTimings()) timed = timed || timing.name == "corner";
  std::string reloadFailure;
  for (const engine::render::Renderer::ShaderReload& reload : renderer.reloadShaders())
    if (reload.feature == "corner" && !reload.status) reloadFailure = reload.status.error().message;

  bool ok = expect(corner[1] > 200 && corner[0] < 40 && corner[2] < 40, "image", "the corner is not the triangle's green");
  ok = expect(opposite[1] <= 100, "image", "the triangle reached the opposite corner") && ok;
  ok = expect(timed, "timings", "no 'corner' scope among the renderer's timings") && ok;
  ok = expect(reloadFailure.empty(), "reload", reloadFailure) && ok;
  ok = expect((*context)->validationMessageCount() == 0, "validation", "the layers reported messages") && ok;
  if (!ok) return 1;
  std::printf("corner_frame: ok\n");
  return 0;
}
