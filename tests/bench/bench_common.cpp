#include "bench_common.h"

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>

#include "engine/scene/gltf/gltf_loader.h"

namespace hsdf::bench {

void require(bool ok, const std::string& what) {
  if (ok) return;
  std::fprintf(stderr, "hsdf_bench: %s\n", what.c_str());
  std::exit(1);
}

const engine::scene::TriangleSoup& bunnySoup() {
  static const engine::scene::TriangleSoup soup = [] {
    auto scene = engine::scene::loadGltf(std::string(HSDF_ASSET_DIR) + "/bunny.glb");
    require(scene.ok(), scene.ok() ? "" : scene.error().message);
    return engine::scene::flattenTriangles(*scene);
  }();
  return soup;
}

const MeshSource& bunnySource() {
  static const std::unique_ptr<MeshSource> source = [] {
    auto created = MeshSource::create(bunnySoup());
    require(created.ok(), created.ok() ? "" : created.error().message);
    return std::move(created.value());
  }();
  return *source;
}

GridSpec bunnyGrid(int resolution) {
  auto grid = fitGrid(bunnySource().bounds(), resolution, kDefaultPaddingCells);
  require(grid.ok(), grid.ok() ? "" : grid.error().message);
  return *grid;
}

const HermiteField& bunnyField(int resolution) {
  static std::mutex mutex;
  static std::map<int, HermiteField> fields;
  const std::lock_guard lock(mutex);
  auto it = fields.find(resolution);
  if (it == fields.end()) {
    auto field = bakeHermiteField(bunnySource(), bunnyGrid(resolution));
    require(field.ok(), field.ok() ? "" : field.error().message);
    it = fields.emplace(resolution, std::move(*field)).first;
  }
  return it->second;
}

}  // namespace hsdf::bench
