// The smallest use of the installed hermite_sdf package: bake an analytic torus through the
// module's bake job, draw one headless frame with the module's render features (the Hermite cells
// drawing it, as every program adds them: hsdf::addRenderFeatures) on the test device
// (HSDF_DEVICE from the ctest's launcher, lavapipe unless HSDF_TEST_DEVICE says otherwise;
// validation layers on) and check the frame against the module's CPU reference ray caster.
// Exit code 0 only when the torus covers the pixels the reference says it covers and the
// validation layers said nothing.
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/render/camera_view.h"
#include "engine/render/renderer.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/reference.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/renderable.h"

namespace {

constexpr std::uint32_t kSize = 64;
// Coverage may differ from the reference only where a pixel centre grazes the silhouette.
constexpr double kMaxDisagreement = 0.01;

int fail(const char* what, const std::string& message) {
  std::fprintf(stderr, "torus_frame: %s: %s\n", what, message.c_str());
  return 1;
}

}  // namespace

int main() {
  // The engine loads SPIR-V from $HSDF_SHADER_DIR (else the folder it was built with): point it at
  // the package's copy, so that this program works once the build tree is gone.
  setenv("HSDF_SHADER_DIR", CONSUMER_SHADER_DIR, 1);

  hsdf::BakeSettings settings;
  settings.resolution = 20;
  hsdf::BakeJob job(hsdf::BakeSource::fromShape("torus"), settings);
  auto baked = job.wait();
  if (!baked) return fail("bake", baked.error().message);
  const std::shared_ptr<const hsdf::SdfAsset> asset = baked.value();

  engine::gpu::ContextDesc desc;
  desc.applicationName = "hermite_sdf consumer";
  // Auto: the device HSDF_DEVICE names, which the ctest's launcher (hsdf_test_device_run) sets
  // from HSDF_TEST_DEVICE (lavapipe unless set); an outside project cannot link the test support.
  desc.device = engine::gpu::DevicePreference::Auto;
  desc.validation = true;
  auto context = engine::gpu::Context::create(desc);
  if (!context) return fail("vulkan", context.error().message);

  engine::render::Renderer renderer(**context, engine::render::RendererDesc{}, VkExtent2D{kSize, kSize});
  if (auto added = hsdf::addRenderFeatures(renderer); !added) return fail("render features", added.error().message);

  engine::ecs::Registry registry;
  const engine::ecs::Entity torus = registry.create();
  registry.emplace<engine::scene::Transform>(torus);
  registry.emplace<engine::scene::WorldTransform>(torus);
  hsdf::HermiteSdfRenderable renderable;
  renderable.asset = asset;
  registry.emplace<hsdf::HermiteSdfRenderable>(torus, renderable);

  // Seen from above at an angle: the hole in the middle must stay empty.
  const glm::vec3 center(asset->surfaceBounds.center());
  const auto camera = engine::render::CameraView::lookAt(center + glm::vec3(0.0f, 2.2f, 1.6f), center, 0.9f, 0.05f, 1.0f);
  renderer.renderFrame(registry, camera);
  const std::vector<float> depth = renderer.readbackDepth();

  auto reference = hsdf::renderReference(asset->field, camera.view, camera.proj, glm::ivec2(kSize), &asset->classification);
  if (!reference) return fail("reference", reference.error().message);

  int gpuHits = 0, referenceHits = 0, disagreements = 0;
  for (std::size_t i = 0; i < depth.size(); ++i) {
    const bool gpuHit = depth[i] > 0.0f;
    gpuHits += gpuHit;
    referenceHits += reference->hit[i];
    disagreements += gpuHit != bool(reference->hit[i]);
  }
  const double disagreement = double(disagreements) / double(depth.size());
  const auto* cells = renderer.feature<hsdf::HermiteCellFeature>();
  std::printf("torus_frame: %zu kept cells, %llu drawn; GPU covers %d pixels, reference %d, %d differ (%.2f%%); "
              "%u validation messages\n",
              asset->cells.records.size(), static_cast<unsigned long long>(cells->stats().cells), gpuHits,
              referenceHits, disagreements, 100.0 * disagreement, (*context)->validationMessageCount());

  if ((*context)->validationMessageCount() != 0) return fail("validation", "the layers reported messages");
  // A torus seen at this distance fills a good part of the 64x64 frame but not all of it.
  if (referenceHits < int(depth.size() / 10) || referenceHits > int(depth.size() * 9 / 10))
    return fail("camera", "the reference does not frame the torus");
  if (disagreement > kMaxDisagreement) return fail("coverage", "the GPU frame differs from the reference");
  return 0;
}
