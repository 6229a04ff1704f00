// png_probe [--crop X,Y,W,H] A.png [B.png]: what the scripted-runner tests check in screenshots,
// one line on stdout:
//   size WxH coverage C [differs D]
// C: share of pixels whose colour differs from the top-left pixel (the background when the object
// is framed in the middle, the ground is off and the panel hidden). D: share of pixels that differ
// between A and B (1 when the sizes differ). --crop: both images cut to that rectangle first (e.g.
// one side of a split screen; size is the cut's). Exit 1 with a message naming the file it cannot
// read or a crop outside it.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>
#include <cstdlib>

#include "engine/core/image_io.h"

namespace {

bool samePixel(const std::uint8_t* a, const std::uint8_t* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

double coverage(const engine::LoadedImage& image) {
  std::size_t covered = 0;
  const std::size_t pixels = std::size_t(image.width) * image.height;
  for (std::size_t i = 0; i < pixels; ++i) covered += samePixel(&image.rgba[4 * i], image.rgba.data()) ? 0 : 1;
  return double(covered) / double(pixels);
}

double differs(const engine::LoadedImage& a, const engine::LoadedImage& b) {
  if (a.width != b.width || a.height != b.height) return 1.0;
  std::size_t different = 0;
  const std::size_t pixels = std::size_t(a.width) * a.height;
  for (std::size_t i = 0; i < pixels; ++i) different += samePixel(&a.rgba[4 * i], &b.rgba[4 * i]) ? 0 : 1;
  return double(different) / double(pixels);
}

struct Crop {
  std::uint32_t x = 0, y = 0, width = 0, height = 0;
};

bool parseCrop(const char* text, Crop& crop) {
  return std::sscanf(text, "%u,%u,%u,%u", &crop.x, &crop.y, &crop.width, &crop.height) == 4 && crop.width > 0 &&
         crop.height > 0;
}

// The image `path`, cut to `crop` when one is given; an error message naming the file otherwise.
bool load(const char* path, const Crop* crop, engine::LoadedImage& image) {
  auto read = engine::readPng(path);
  if (!read) {
    std::fprintf(stderr, "png_probe: %s\n", read.error().message.c_str());
    return false;
  }
  image = std::move(*read);
  if (!crop) return true;
  if (std::uint64_t(crop->x) + crop->width > image.width || std::uint64_t(crop->y) + crop->height > image.height) {
    std::fprintf(stderr, "png_probe: --crop %u,%u,%u,%u is outside %s (%ux%u)\n", crop->x, crop->y, crop->width,
                 crop->height, path, image.width, image.height);
    return false;
  }
  engine::LoadedImage cut{crop->width, crop->height, std::vector<std::uint8_t>(4u * crop->width * crop->height)};
  for (std::uint32_t row = 0; row < crop->height; ++row)
    std::copy_n(&image.rgba[4 * ((std::size_t(crop->y) + row) * image.width + crop->x)], 4 * crop->width,
                &cut.rgba[4 * std::size_t(row) * crop->width]);
  image = std::move(cut);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Crop crop;
  const bool cropped = argc >= 3 && std::strcmp(argv[1], "--crop") == 0;
  if (cropped && !parseCrop(argv[2], crop)) {
    std::fprintf(stderr, "png_probe: --crop '%s' is not X,Y,W,H with W,H > 0\n", argv[2]);
    return 2;
  }
  const int first = cropped ? 3 : 1;
  if (argc - first < 1 || argc - first > 2) {
    std::fprintf(stderr, "usage: png_probe [--crop X,Y,W,H] A.png [B.png]\n");
    return 2;
  }
  engine::LoadedImage a, b;
  if (!load(argv[first], cropped ? &crop : nullptr, a)) return 1;
  std::printf("size %ux%u coverage %.4f", a.width, a.height, coverage(a));
  if (argc - first == 2) {
    if (!load(argv[first + 1], cropped ? &crop : nullptr, b)) return 1;
    std::printf(" differs %.4f", differs(a, b));
  }
  std::printf("\n");
  return 0;
}
