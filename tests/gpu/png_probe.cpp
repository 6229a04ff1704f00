// png_probe A.png [B.png]: what the scripted-runner tests check in screenshots, one line on stdout:
//   size WxH coverage C [differs D]
// C: share of pixels whose colour differs from the top-left pixel (the background when the object
// is framed in the middle, the ground is off and the panel hidden). D: share of pixels that differ
// between A and B (1 when the sizes differ). Exit 1 with a message naming the file it cannot read.
#include <cstdio>
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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: png_probe A.png [B.png]\n");
    return 2;
  }
  const auto a = engine::readPng(argv[1]);
  if (!a) {
    std::fprintf(stderr, "png_probe: %s\n", a.error().message.c_str());
    return 1;
  }
  std::printf("size %ux%u coverage %.4f", a->width, a->height, coverage(*a));
  if (argc == 3) {
    const auto b = engine::readPng(argv[2]);
    if (!b) {
      std::fprintf(stderr, "\npng_probe: %s\n", b.error().message.c_str());
      return 1;
    }
    std::printf(" differs %.4f", differs(*a, *b));
  }
  std::printf("\n");
  return 0;
}
