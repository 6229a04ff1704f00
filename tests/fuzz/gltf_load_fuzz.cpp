// Fuzz target: arbitrary bytes through the glTF importer (GLB container checks, JSON sanitising,
// tinygltf, accessor/node validation, triangle flattening). Any result is fine; a crash, hang,
// sanitizer report or runaway allocation is a bug. No base directory is given, so the importer
// never touches the file system.
#include <cstddef>
#include <cstdint>
#include <span>

#include "engine/core/log.h"
#include "engine/scene/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Warnings about skipped primitives would flood the fuzzer's output.
  static const bool quiet = [] {
    engine::log::setMinLevel(engine::log::Level::Error);
    return true;
  }();
  (void)quiet;
  const auto scene = engine::scene::loadGltfFromMemory(std::span<const std::uint8_t>(data, size), "fuzz-input", {});
  if (scene.ok()) (void)engine::scene::flattenTriangles(*scene);
  return 0;
}
