#include "engine/core/image_io.h"

#include "engine/core/files.h"

#include <limits>
#include <string>
#include <vector>

#include <stb_image.h>
#include <stb_image_write.h>

namespace engine {
namespace {

// stb_image's RGBA pixels as a LoadedImage; frees them.
LoadedImage takePixels(stbi_uc* data, int width, int height) {
  LoadedImage image;
  image.width = std::uint32_t(width);
  image.height = std::uint32_t(height);
  image.rgba.assign(data, data + std::size_t(width) * std::size_t(height) * 4);
  stbi_image_free(data);
  return image;
}

}  // namespace

Status writePng(const std::filesystem::path& path, std::span<const std::uint8_t> pixels, std::uint32_t width,
                std::uint32_t height, std::uint32_t channels) {
  if (channels < 1 || channels > 4 || width == 0 || height == 0)
    return makeError(path.string() + ": cannot write a " + std::to_string(width) + "x" + std::to_string(height) +
                     " image with " + std::to_string(channels) + " channels");
  if (pixels.size() < std::size_t(width) * height * channels)
    return makeError(path.string() + ": pixel buffer smaller than the image");
  // Encoded in memory and written by writeBinaryFile: stbi_write_png checks neither its writes nor
  // the close, and a full disk left a truncated PNG behind a success.
  std::vector<std::uint8_t> encoded;
  const auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    out->insert(out->end(), static_cast<const std::uint8_t*>(data), static_cast<const std::uint8_t*>(data) + size);
  };
  const int ok = stbi_write_png_to_func(append, &encoded, int(width), int(height), int(channels), pixels.data(),
                                        int(width * channels));
  if (!ok) return makeError(path.string() + ": cannot encode PNG");
  return writeBinaryFile(path, encoded);
}

Expected<LoadedImage> readPng(const std::filesystem::path& path) {
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load(path.string().c_str(), &w, &h, &n, 4);
  if (!data) return makeError(path.string() + ": cannot read image: " + stbi_failure_reason());
  return takePixels(data, w, h);
}

Expected<LoadedImage> decodeImage(std::span<const std::uint8_t> encoded, std::uint32_t maxSide) {
  if (encoded.empty()) return makeError("cannot decode image: no bytes");
  if (encoded.size() > std::size_t(std::numeric_limits<int>::max()))
    return makeError("cannot decode image: " + std::to_string(encoded.size()) + " bytes is over stb_image's 2 GiB");
  const int length = int(encoded.size());
  int w = 0, h = 0, n = 0;
  if (!stbi_info_from_memory(encoded.data(), length, &w, &h, &n))
    return makeError(std::string("cannot decode image: ") + stbi_failure_reason());
  if (w <= 0 || h <= 0 || std::uint32_t(w) > maxSide || std::uint32_t(h) > maxSide)
    return makeError("image is " + std::to_string(w) + "x" + std::to_string(h) + ", over the limit of " +
                     std::to_string(maxSide) + " texels a side");
  stbi_uc* data = stbi_load_from_memory(encoded.data(), length, &w, &h, &n, 4);
  if (!data) return makeError(std::string("cannot decode image: ") + stbi_failure_reason());
  return takePixels(data, w, h);
}

}  // namespace engine
