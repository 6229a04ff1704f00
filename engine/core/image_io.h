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

// Decodes a PNG or JPEG (whatever stb_image reads) held in memory into RGBA8. The size in the
// header is checked before any pixel is decoded: an image wider or taller than `maxSide` is
// refused (a few hundred bytes of PNG can claim 65535 x 65535 pixels, 16 GiB).
Expected<LoadedImage> decodeImage(std::span<const std::uint8_t> encoded, std::uint32_t maxSide);

}  // namespace engine
