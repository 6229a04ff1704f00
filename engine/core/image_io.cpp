#include "engine/core/image_io.h"

#include <string>
#include <vector>

#include <stb_image.h>
#include <stb_image_write.h>

namespace engine {

Status writePng(const std::filesystem::path& path, std::span<const std::uint8_t> pixels, std::uint32_t width,
                std::uint32_t height, std::uint32_t channels) {
  if (channels < 1 || channels > 4 || width == 0 || height == 0)
    return makeError(path.string() + ": cannot write a " + std::to_string(width) + "x" + std::to_string(height) +
                     " image with " + std::to_string(channels) + " channels");
  if (pixels.size() < std::size_t(width) * height * channels)
    return makeError(path.string() + ": pixel buffer smaller than the image");
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
  }
  const int ok = stbi_write_png(path.string().c_str(), int(width), int(height), int(channels), pixels.data(),
                                int(width * channels));
  if (!ok) return makeError(path.string() + ": cannot write PNG");
  return {};
}

Expected<LoadedImage> readPng(const std::filesystem::path& path) {
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load(path.string().c_str(), &w, &h, &n, 4);
  if (!data) return makeError(path.string() + ": cannot read image: " + stbi_failure_reason());
  LoadedImage image;
  image.width = std::uint32_t(w);
  image.height = std::uint32_t(h);
  image.rgba.assign(data, data + std::size_t(w) * std::size_t(h) * 4);
  stbi_image_free(data);
  return image;
}

}  // namespace engine
