#pragma once
// PNG output for screenshots, debug images and test artefacts.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "engine/core/expected.h"

namespace engine {

// Writes tightly packed 8-bit pixels with `channels` (1, 3 or 4) per pixel.
Status writePng(const std::filesystem::path& path, std::span<const std::uint8_t> pixels, std::uint32_t width,
                std::uint32_t height, std::uint32_t channels);

struct LoadedImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba;  // 4 channels
};
Expected<LoadedImage> readPng(const std::filesystem::path& path);

}  // namespace engine
