// Fuzz target: arbitrary bytes through the glTF importer (GLB container checks, JSON sanitising,
// tinygltf, accessor/node validation, triangle flattening). An error is a fine answer; a crash,
// hang, sanitizer report or runaway allocation is a bug, and so is an accepted scene that breaks
// the importer's promises (indices in range, one normal per position, finite positions, parents
// before children). No base directory is given, so the importer never touches the file system.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "engine/core/log.h"
#include "fuzz_check.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "engine/scene/scene_pose.h"

namespace {
constexpr std::uint64_t kMaxFlattenedVertices = std::uint64_t(1) << 20;  // 12 MB of positions
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Warnings about skipped primitives would flood the fuzzer's output.
  static const bool quiet = [] {
    engine::log::setMinLevel(engine::log::Level::Error);
    return true;
  }();
  (void)quiet;
  const auto scene = engine::scene::loadGltfFromMemory(std::span<const std::uint8_t>(data, size), "fuzz-input", {});
  if (!scene.ok()) return 0;
  for (const auto& mesh : scene->meshes) {
    for (const auto& primitive : mesh.primitives) {
      FUZZ_CHECK(primitive.normals.size() == primitive.positions.size());
      FUZZ_CHECK(primitive.indices.size() % 3 == 0);
      for (std::uint32_t index : primitive.indices) FUZZ_CHECK(index < primitive.positions.size());
      for (const auto& p : primitive.positions) FUZZ_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
      FUZZ_CHECK(primitive.texcoords.empty() || primitive.texcoords.size() == primitive.positions.size());
    }
  }
  // Textures: what the renderer uploads must be whole, and a material names a texture that exists.
  for (const auto& texture : scene->textures)
    FUZZ_CHECK(texture.width > 0 && texture.height > 0 &&
               texture.rgba.size() == std::size_t(texture.width) * texture.height * 4);
  for (const auto& material : scene->materials)
    for (const int texture : {material.baseColorTexture, material.metallicRoughnessTexture, material.occlusionTexture,
                              material.emissiveTexture})
      FUZZ_CHECK(texture >= -1 && texture < int(scene->textures.size()));
  for (std::size_t n = 0; n < scene->nodes.size(); ++n) {
    FUZZ_CHECK(scene->nodes[n].parent < int(n));
    FUZZ_CHECK(scene->nodes[n].mesh < int(scene->meshes.size()));
  }
  // Animations: what posing indexes is in range, and posing any of them at any time stays inside it.
  for (const auto& animation : scene->animations) {
    for (const auto& channel : animation.channels) {
      FUZZ_CHECK(channel.node >= 0 && channel.node < int(scene->nodes.size()));
      FUZZ_CHECK(channel.sampler >= 0 && channel.sampler < int(animation.samplers.size()));
    }
    for (const auto& sampler : animation.samplers) {
      const std::size_t perKey = sampler.interpolation == engine::scene::Interpolation::CubicSpline ? 3 : 1;
      FUZZ_CHECK(!sampler.times.empty() && sampler.values.size() == perKey * sampler.times.size());
      for (std::size_t k = 1; k < sampler.times.size(); ++k) FUZZ_CHECK(sampler.times[k] > sampler.times[k - 1]);
    }
    engine::scene::SceneData posed = *scene;
    const engine::scene::RestPose rest = engine::scene::restPose(posed);
    for (const float t : {-1.0f, 0.0f, 0.5f * engine::scene::duration(animation), 1e9f})
      engine::scene::poseScene(posed, rest, animation, t);
  }
  // Flattening copies a mesh per node that places it: without this limit a few kilobytes of nodes
  // make it allocate gigabytes (which is what checkFlattenable is for).
  if (!engine::scene::checkFlattenable(*scene, kMaxFlattenedVertices).ok()) return 0;
  const engine::scene::TriangleSoup soup = engine::scene::flattenTriangles(*scene);
  for (std::uint32_t index : soup.indices) FUZZ_CHECK(index < soup.positions.size());
  return 0;
}
