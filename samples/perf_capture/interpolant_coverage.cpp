// interpolant_coverage: how far each interpolant's own surface lies from the mesh, traced exactly on
// the CPU (hsdf::renderReference: the degree-9 / degree-3 polynomial of each cell along the ray), so
// that a tracer's coverage mismatch in the perf capture can be split into the interpolant's share
// and the tracer's (trilinear sphere tracing draws 2.2-3.4x dense Hermite's mismatch at
// the same K; is that the tracer or the trilinear interpolant itself?).
//   interpolant_coverage [--scene FILE.glb] [--size WxH] [--resolutions 16,32,...] [--views N]
// Prints a markdown table: per K, pixels per view whose hit/miss differs from the mesh for the
// exact tricubic Hermite and the exact trilinear interpolant of the same samples, and their ratio.
// The samples come from the module's one bake pipeline (hsdf::bakeAsset, a dense field, padding 1),
// so the mesh is prepared (welded, signed, open parts dropped) as every other tool bakes it.
// The views orbit the mesh's bounds (yaw 0.3 + v * 90 deg, pitch 20 deg, the bounds' diagonal
// filling ~1.2 of the 0.8 rad vertical field of view), not the perf capture's views.
#include <cmath>
#include <cstdio>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/core/math.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "ground_truth.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/reference.h"
#include "options_common.h"

namespace {

std::vector<engine::render::CameraView> orbitCameras(const hsdf::Aabb& bounds, int views, float aspect) {
  const glm::vec3 centre = glm::vec3((bounds.min + bounds.max) * 0.5);
  const float diagonal = float(glm::length(bounds.max - bounds.min));
  std::vector<engine::render::CameraView> cameras;
  for (int v = 0; v < views; ++v) {
    engine::render::CameraView camera;
    camera.fovY = 0.8f;
    camera.znear = 0.01f * diagonal;
    camera.position = engine::math::orbitEye(centre, 0.6f * diagonal / std::tan(0.4f), 0.3f + float(v) * 1.5707964f, 0.35f);
    camera.view = engine::math::lookAt(camera.position, centre, glm::vec3(0.0f, 1.0f, 0.0f));
    camera.proj = engine::math::perspectiveReverseZInfinite(camera.fovY, aspect, camera.znear);
    cameras.push_back(camera);
  }
  return cameras;
}

// Pixels whose hit/miss differs from the truth's.
double mismatch(const hsdf::ReferenceImage& image, const capture::TruthImage& truth) {
  double count = 0.0;
  for (std::size_t i = 0; i < image.hit.size(); ++i) count += (image.hit[i] != 0) != truth.hit(i) ? 1.0 : 0.0;
  return count;
}

int fail(const std::string& message) {
  std::fprintf(stderr, "interpolant_coverage: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Coverage mismatch against the mesh of the exact Hermite and trilinear interpolants, per K");
  std::string scenePath = samples::defaultScenePath().string();
  std::uint32_t width = 960, height = 540;
  std::vector<int> resolutions{16, 32, 64, 128};
  int views = 4;
  app.add_option("--scene", scenePath, "glTF/GLB mesh (default: the bunny)");
  samples::addSizeOption(app, width, height, "image size WxH (default 960x540)");
  app.add_option("--resolutions", resolutions, "K, samples per axis, 4..512 (default 16,32,64,128)")
      ->delimiter(',')
      ->check(CLI::Range(4, 512));
  app.add_option("--views", views, "orbit views 1..8 (default 4)")->check(CLI::Range(1, 8));
  if (auto stop = samples::parseCommandLine(app, "interpolant_coverage", argc, argv)) {
    std::fprintf(stop->exitCode ? stderr : stdout, "%s\n", stop->message.c_str());
    return stop->exitCode;
  }

  auto scene = engine::scene::loadGltf(scenePath);
  if (!scene.ok()) return fail(scenePath + ": " + scene.error().message);
  auto source = hsdf::BakeSource::fromScene(scenePath, *scene);
  if (!source.ok()) return fail(scenePath + ": " + source.error().message);
  auto prepared = hsdf::prepareSource(*source, hsdf::BakeSettings{});
  if (!prepared.ok()) return fail(scenePath + ": " + prepared.error().message);
  hsdf::logPreparedSource(*prepared);
  const std::unique_ptr<capture::TruthSurface> surface = capture::meshSurface(*source->triangles);
  const auto cameras = orbitCameras(prepared->source->bounds(), views, float(width) / float(height));
  std::vector<capture::TruthImage> truth;
  for (const auto& camera : cameras) truth.push_back(capture::castTruth(*surface, camera, int(width), int(height)));

  std::printf("| K | exact Hermite (px/view) | exact trilinear (px/view) | trilinear / Hermite |\n|---|---|---|---|\n");
  for (const int k : resolutions) {
    hsdf::BakeSettings settings;
    settings.resolution = k;
    settings.padding = 1;
    settings.band = hsdf::BakeBand::Dense;  // the dense samples both interpolants are made of
    auto asset = hsdf::bakeAsset(*prepared, settings);
    if (!asset.ok()) return fail(asset.error().message);
    const hsdf::HermiteField& hermite = (*asset)->field;
    hsdf::TrilinearField trilinear;  // the f of the same samples: what the trilinear tracer's texture holds
    trilinear.grid = hermite.grid;
    for (const hsdf::HermiteSample& s : hermite.samples) trilinear.values.push_back(s.f);
    double hermiteMismatch = 0.0, trilinearMismatch = 0.0;
    for (std::size_t v = 0; v < cameras.size(); ++v) {
      const glm::ivec2 imageSize{int(width), int(height)};
      auto h = hsdf::renderReference(hermite, cameras[v].view, cameras[v].proj, imageSize);
      auto t = hsdf::renderReference(trilinear, cameras[v].view, cameras[v].proj, imageSize);
      if (!h.ok() || !t.ok()) return fail((h.ok() ? t.error() : h.error()).message);
      hermiteMismatch += mismatch(*h, truth[v]);
      trilinearMismatch += mismatch(*t, truth[v]);
    }
    const double n = double(cameras.size());
    std::printf("| %d | %.1f | %.1f | %.2f |\n", k, hermiteMismatch / n, trilinearMismatch / n,
                hermiteMismatch > 0.0 ? trilinearMismatch / hermiteMismatch : 0.0);
    std::fflush(stdout);
  }
  return 0;
}
